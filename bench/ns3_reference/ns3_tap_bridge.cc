// SPDX-License-Identifier: GPL-2.0-only (links ns-3; see LICENSE in this folder)
//
// ns-3 3.37 as the medium between two sitlnet robots, set up as DANCERS and
// ns-3's own tap-wifi examples do: one ghost node per robot whose 802.11a ad
// hoc WifiNetDevice is joined to the robot's wlan0 TAP by ns-3's TapBridge in
// UseLocal mode, the real-time simulator, a Yans channel with the loss model
// of bench/ns3_reference's saturation matrix. tcp_side_by_side.sh runs it
// and `sitlnet medium` in turn under the same iperf3 flow.
//
// Usage: ns3_tap_bridge NETNS_A NETNS_B DISTANCE_M RADIO
//   RADIO: an 802.11a rate in Mb/s (54), or 802.11n at 5 GHz, 20 MHz: ht-mcsM (no A-MPDU) or
//   ht-mcsM-ampdu (ns-3's A-MPDU defaults), M in 0..7; or 802.11ac at WIDTH MHz (20, 40, 80):
//   vht-mcsM-WIDTH (no A-MPDU) or vht-mcsM-WIDTH-ampdu (best effort's A-MPDU limit at VHT's
//   maximum, 1048575 B: 64 MPDUs of 1500 B), M in 0..9.
//   Prints "ready" once both TAPs are attached; runs until SIGTERM or SIGINT;
//   then prints the MAC-level counters of both devices and exits 0.
//
// Two things of Debian's packaging and of ns-3 3.37 are worked around here,
// neither changes what is simulated:
// - libns3-tap-bridge.so execs its TAP opener ("tap-creator") at the path of
//   Debian's build tree, which the package does not ship; the opener is in
//   Debian's `ns3` package under /usr/libexec/ns3. execlp() is defined below,
//   so the library's call resolves to it (the executable comes first in the
//   dynamic linker's lookup), and it runs the packaged opener instead.
// - Each robot's TAP is called wlan0 in its own network namespace, and the
//   opener looks the name up in the namespace it runs in; it also answers on
//   an abstract Unix socket, which is the namespace's own. So the simulator's
//   thread enters robot A's namespace just before A's TapBridge starts (the
//   socket and the opener are made there), B's before B's, and comes home.
// - In UseLocal mode TapBridge gives the WifiNetDevice the TAP's MAC address
//   when the first frame comes by, but ns-3 3.37's frame exchange manager
//   keeps the address it was built with, so unicast frames to the robot would
//   go unacknowledged. Both get the TAP's address before the run instead.
#include <fcntl.h>
#include <net/if.h>
#include <pthread.h>
#include <sched.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>
#include <thread>
#include <vector>

#include "ns3/core-module.h"
#include "ns3/network-module.h"
#include "ns3/tap-bridge-module.h"
#include "ns3/wifi-module.h"
#include "ns3_two_stations.h"

namespace {

constexpr const char* kPackagedTapCreator = "/usr/libexec/ns3/ns3.37-tap-creator";
constexpr const char* kTapName = "wlan0";
int OpenNetns(const std::string& name) {
  const std::string path = "/run/netns/" + name;
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    std::fprintf(stderr, "ns3_tap_bridge: %s: %s\n", path.c_str(), std::strerror(errno));
    std::exit(1);
  }
  return fd;
}

void EnterNetns(int netns_fd) {
  if (setns(netns_fd, CLONE_NEWNET) != 0) {
    std::fprintf(stderr, "ns3_tap_bridge: setns: %s\n", std::strerror(errno));
    std::exit(1);
  }
}

// The MAC address of wlan0 in the namespace `netns_fd` (this thread enters
// it and comes back to `home_netns_fd`).
ns3::Mac48Address TapMac(int netns_fd, int home_netns_fd, const std::string& netns_name) {
  EnterNetns(netns_fd);
  const int sock = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ifreq request{};
  std::strncpy(request.ifr_name, kTapName, IFNAMSIZ - 1);
  const bool found = sock >= 0 && ioctl(sock, SIOCGIFHWADDR, &request) == 0;
  const int saved_errno = errno;
  if (sock >= 0) close(sock);
  EnterNetns(home_netns_fd);
  if (!found) {
    std::fprintf(stderr, "ns3_tap_bridge: %s has no %s: %s\n", netns_name.c_str(), kTapName,
                 std::strerror(saved_errno));
    std::exit(1);
  }
  ns3::Mac48Address mac;
  mac.CopyFrom(reinterpret_cast<const uint8_t*>(request.ifr_hwaddr.sa_data));
  return mac;
}

// Per robot: frames handed to the MAC (from the TAP), PHY transmissions
// (DATA, retries and ACKs).
uint64_t g_mac_tx[2] = {0, 0};
uint64_t g_phy_tx[2] = {0, 0};
void OnMacTx(int robot, ns3::Ptr<const ns3::Packet>) { ++g_mac_tx[robot]; }
void OnPhyTxBegin(int robot, ns3::Ptr<const ns3::Packet>, double) { ++g_phy_tx[robot]; }
// How late the real-time simulator hands received frames up (and so to the
// TAP): wall time minus simulated time at the end of each reception, in us.
std::vector<int64_t> g_lateness_us;
void OnPhyRxEnd(ns3::Ptr<ns3::RealtimeSimulatorImpl> impl, ns3::Ptr<const ns3::Packet>) {
  g_lateness_us.push_back((impl->RealtimeNow() - ns3::Simulator::Now()).GetMicroSeconds());
}
uint64_t g_mac_tx_drops = 0;
void OnMacTxDrop(ns3::Ptr<const ns3::Packet>) { ++g_mac_tx_drops; }
uint64_t g_retransmissions = 0;
void OnMpduResponseTimeout(uint8_t, ns3::Ptr<const ns3::WifiMpdu>, const ns3::WifiTxVector&) {
  ++g_retransmissions;
}

// RADIO's n/ac forms (the usage above); false for anything else, malformed n/ac names included.
bool ParseQosRadio(const std::string& radio, Ns3QosRadio* qos) {
  int mcs = -1, width_mhz = 20, consumed = 0;
  if (std::sscanf(radio.c_str(), "ht-mcs%d%n", &mcs, &consumed) == 1) {
    qos->vht = false;
    if (mcs < 0 || mcs > 7) return false;
  } else if (std::sscanf(radio.c_str(), "vht-mcs%d-%d%n", &mcs, &width_mhz, &consumed) == 2) {
    qos->vht = true;
    if (mcs < 0 || mcs > 9 || (width_mhz != 20 && width_mhz != 40 && width_mhz != 80)) {
      return false;
    }
  } else {
    return false;
  }
  const std::string rest = radio.substr(static_cast<size_t>(consumed));
  if (!rest.empty() && rest != "-ampdu") return false;
  qos->mcs = mcs;
  qos->width_mhz = width_mhz;
  qos->be_max_ampdu_bytes = rest.empty() ? 0 : qos->vht ? 1048575 : 65535;
  return true;
}

}  // namespace

// Called by libns3-tap-bridge.so in its forked child (see the top of the
// file). Only async-signal-safe calls: the parent has other threads.
extern "C" int execlp(const char* file, const char* arg, ...) {
  constexpr int kMaxArguments = 32;
  const char* argv[kMaxArguments + 1];
  int argc = 0;
  argv[argc++] = arg;
  va_list list;
  va_start(list, arg);
  for (const char* next = va_arg(list, const char*); next != nullptr;
       next = va_arg(list, const char*)) {
    if (argc == kMaxArguments) {
      va_end(list);
      errno = E2BIG;
      return -1;
    }
    argv[argc++] = next;
  }
  va_end(list);
  argv[argc] = nullptr;
  const size_t length = std::strlen(file);
  const char* suffix = "-tap-creator";
  const size_t suffix_length = std::strlen(suffix);
  const bool is_tap_creator =
      length >= suffix_length && std::strcmp(file + length - suffix_length, suffix) == 0;
  if (!is_tap_creator) return execvp(file, const_cast<char* const*>(argv));  // As libc's.
  argv[0] = kPackagedTapCreator;
  return execv(kPackagedTapCreator, const_cast<char* const*>(argv));
}

int main(int argc, char** argv) {
  using namespace ns3;
  if (argc != 5) {
    std::fprintf(stderr,
                 "usage: ns3_tap_bridge NETNS_A NETNS_B DISTANCE_M RADIO (54, ht-mcs7, "
                 "ht-mcs7-ampdu, vht-mcs9-80-ampdu)\n");
    return 2;
  }
  if (access(kPackagedTapCreator, X_OK) != 0) {
    std::fprintf(stderr, "ns3_tap_bridge: %s missing (Debian package ns3)\n", kPackagedTapCreator);
    return 1;
  }
  const std::vector<std::string> netns = {argv[1], argv[2]};
  const double distance_m = std::stod(argv[3]);
  const std::string radio = argv[4];
  Ns3QosRadio qos;
  const bool is_qos = ParseQosRadio(radio, &qos);
  if (!is_qos && (radio.rfind("ht-", 0) == 0 || radio.rfind("vht-", 0) == 0)) {
    std::fprintf(stderr,
                 "ns3_tap_bridge: RADIO %s: want ht-mcsM[-ampdu] (M 0..7) or "
                 "vht-mcsM-WIDTH[-ampdu] (M 0..9, WIDTH 20, 40, 80)\n",
                 radio.c_str());
    return 2;
  }

  // Blocked here, so every thread made later (ns-3's TAP readers too) has it
  // blocked and only the watcher below takes it.
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGINT);
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

  GlobalValue::Bind("SimulatorImplementationType", StringValue("ns3::RealtimeSimulatorImpl"));
  GlobalValue::Bind("ChecksumEnabled", BooleanValue(true));

  const Ns3TwoStations stations = is_qos ? MakeTwoQosStations(distance_m, qos)
                                         : MakeTwo80211aStations(distance_m, std::stod(radio));
  const NodeContainer& nodes = stations.nodes;
  const NetDeviceContainer& devices = stations.devices;

  TapBridgeHelper tap_bridge;
  tap_bridge.SetAttribute("Mode", StringValue("UseLocal"));
  tap_bridge.SetAttribute("DeviceName", StringValue(kTapName));
  const int home_netns_fd = open("/proc/thread-self/ns/net", O_RDONLY | O_CLOEXEC);
  if (home_netns_fd < 0) {
    std::fprintf(stderr, "ns3_tap_bridge: own network namespace: %s\n", std::strerror(errno));
    return 1;
  }
  std::vector<int> netns_fds = {home_netns_fd};
  for (int i = 0; i < 2; ++i) {
    const int netns_fd = OpenNetns(netns[i]);
    netns_fds.push_back(netns_fd);
    const Mac48Address tap_mac = TapMac(netns_fd, home_netns_fd, netns[i]);
    Ptr<WifiNetDevice> device = DynamicCast<WifiNetDevice>(devices.Get(i));
    device->SetAddress(tap_mac);
    device->GetMac()->GetFrameExchangeManager()->SetAddress(tap_mac);
    // Enter at 2i us, the bridge starts at 2i+1 us. (TapBridge schedules its
    // start in its constructor, before attributes apply: Start() moves it.)
    Simulator::Schedule(MicroSeconds(2 * i), [netns_fd] { EnterNetns(netns_fd); });
    DynamicCast<TapBridge>(tap_bridge.Install(nodes.Get(i), device))
        ->Start(MicroSeconds(2 * i + 1));
  }
  Simulator::Schedule(MicroSeconds(4), [home_netns_fd] { EnterNetns(home_netns_fd); });
  // Looked up once, not on every reception.
  const Ptr<RealtimeSimulatorImpl> realtime =
      DynamicCast<RealtimeSimulatorImpl>(Simulator::GetImplementation());
  for (int i = 0; i < 2; ++i) {
    Ptr<WifiNetDevice> device = DynamicCast<WifiNetDevice>(devices.Get(i));
    device->GetMac()->TraceConnectWithoutContext("MacTx", MakeBoundCallback(&OnMacTx, i));
    device->GetPhy()->TraceConnectWithoutContext("PhyTxBegin", MakeBoundCallback(&OnPhyTxBegin, i));
    device->GetPhy()->TraceConnectWithoutContext("PhyRxEnd",
                                                 MakeBoundCallback(&OnPhyRxEnd, realtime));
  }
  Config::ConnectWithoutContext("/NodeList/*/DeviceList/*/$ns3::WifiNetDevice/Mac/MacTxDrop",
                                MakeCallback(&OnMacTxDrop));
  Config::ConnectWithoutContext(
      "/NodeList/*/DeviceList/*/$ns3::WifiNetDevice/Mac/MpduResponseTimeout",
      MakeCallback(&OnMpduResponseTimeout));

  // By 1 ms both TAPs are open.
  Simulator::Schedule(MilliSeconds(1), [] {
    std::printf("ready\n");
    std::fflush(stdout);
  });
  // The real-time simulator takes events from other threads.
  std::thread signal_watch([&stop_signals] {
    int signal_number = 0;
    sigwait(&stop_signals, &signal_number);
    Simulator::ScheduleWithContext(0xffffffff, Seconds(0), [] { Simulator::Stop(); });
  });
  Simulator::Run();
  signal_watch.join();
  for (int i = 0; i < 2; ++i) {
    std::printf("robot %s: to the MAC %llu, PHY transmissions %llu\n", netns[i].c_str(),
                static_cast<unsigned long long>(g_mac_tx[i]),
                static_cast<unsigned long long>(g_phy_tx[i]));
  }
  if (!g_lateness_us.empty()) {
    std::sort(g_lateness_us.begin(), g_lateness_us.end());
    const size_t n = g_lateness_us.size();
    std::printf("receptions %zu, lateness p50 %lld us p99 %lld us max %lld us\n", n,
                static_cast<long long>(g_lateness_us[n / 2]),
                static_cast<long long>(g_lateness_us[n * 99 / 100]),
                static_cast<long long>(g_lateness_us.back()));
  }
  std::printf("ns-3 counters: MAC drops %llu, ACK timeouts %llu\n",
              static_cast<unsigned long long>(g_mac_tx_drops),
              static_cast<unsigned long long>(g_retransmissions));
  Simulator::Destroy();
  for (const int fd : netns_fds) close(fd);
  return 0;
}
