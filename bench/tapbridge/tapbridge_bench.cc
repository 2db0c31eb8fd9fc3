// Medium daemon benchmark: N robots (default 64) all offering unicast
// 1512-byte frames to their ring neighbour (station i -> i+1, as in the ns-3
// Bianchi tables) so that 802.11a at 54 Mb/s is saturated, in real time.
// Measures, per configuration and repetition, the daemon's CPU (utime+stime
// from /proc over the window) and the delivery lateness it records (wall
// instant written - wall instant due, p50/p99), then prints medians:
//   medium  - `sitlnet medium` with the 802.11 model (mac_phy_sim)
//   relay   - `sitlnet medium --relay`: the same TAP I/O and loop, no model
//             (every frame delivered at once): the floor.
// Traffic enters through AF_PACKET sockets bound to each robot's wlan0, so
// it crosses the robot's TAP like any program's frames, without ARP.
//
// Usage (root): tapbridge_bench [--robots N] [--seconds S] [--repeat R]
//                               [--offered-mbps M] [--sitlnet PATH] [--spin-us N]
#include <linux/if_packet.h>
#include <net/ethernet.h>
#include <net/if.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "nns/nns.h"
#include "sitlnet/medium.pb.h"
#include "tapbridge/tapbridge.h"

namespace {

using sitlnet::kNsPerMs;
using sitlnet::kNsPerS;
using sitlnet::TimeNs;

struct Options {
  int robots = 64;
  int seconds = 5;
  int repeat = 3;
  double offered_mbps = 64;  // Total, over all robots: 2x the 54 Mb/s capacity.
  std::string sitlnet = "build/bin/sitlnet";
  std::string spin_us = "0";  // Forwarded to sitlnet medium --spin-us.
};

struct Sample {
  double cpu_percent = 0;
  double p50_us = 0, p99_us = 0;
  double delivered_per_s = 0;
};

TimeNs ProcessCpuNs(pid_t pid) {
  std::ifstream stat("/proc/" + std::to_string(pid) + "/stat");
  std::string text((std::istreambuf_iterator<char>(stat)), std::istreambuf_iterator<char>());
  std::istringstream fields(text.substr(text.rfind(')') + 2));
  std::string field;
  long utime = 0, stime = 0;
  for (int i = 3; i <= 15 && fields >> field; ++i) {
    if (i == 14) utime = std::stol(field);
    if (i == 15) stime = std::stol(field);
  }
  return (utime + stime) * (kNsPerS / sysconf(_SC_CLK_TCK));
}

// One AF_PACKET socket per robot, opened inside its namespace.
std::vector<int> OpenSenders(const sitlnet::Scenario& scenario) {
  std::vector<int> fds;
  for (const sitlnet::RobotPlan& robot : scenario.robots) {
    sitlnet::nns::ScopedNetns inside(robot.netns);
    const int fd = socket(AF_PACKET, SOCK_RAW | SOCK_CLOEXEC, 0);
    sockaddr_ll address{};
    address.sll_family = AF_PACKET;
    address.sll_ifindex = static_cast<int>(if_nametoindex("wlan0"));
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
      throw sitlnet::Error(
          sitlnet::SystemErrorMessage("AF_PACKET socket in " + robot.netns, errno));
    }
    fds.push_back(fd);
  }
  return fds;
}

// Sends round-robin from every robot at the total offered rate, on absolute
// deadlines, until `stop`.
void Offer(const std::vector<int>& fds, double offered_mbps, const std::atomic<bool>& stop) {
  const int n = static_cast<int>(fds.size());
  constexpr int kFrameBytes = 1512;  // 1470-byte UDP payload as an Ethernet frame.
  const TimeNs interval_ns = static_cast<TimeNs>(kFrameBytes * 8 / offered_mbps * 1000);
  std::vector<uint8_t> frame(kFrameBytes, 0);
  TimeNs next = sitlnet::MonotonicNowNs();
  for (int k = 0; !stop.load(std::memory_order_relaxed); k = (k + 1) % n) {
    const sitlnet::MacAddress dst = sitlnet::RobotMac((k + 1) % n);
    const sitlnet::MacAddress src = sitlnet::RobotMac(k);
    std::memcpy(frame.data(), dst.bytes.data(), 6);
    std::memcpy(frame.data() + 6, src.bytes.data(), 6);
    frame[12] = 0x88;  // Local experimental ethertype: receivers' stacks drop it.
    frame[13] = 0xb5;
    send(fds[k], frame.data(), frame.size(), MSG_DONTWAIT);
    next += interval_ns;
    timespec ts{static_cast<time_t>(next / kNsPerS), static_cast<long>(next % kNsPerS)};
    clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr);
  }
}

sitlnet::proto::MediumStatus Status(const std::string& scenario) {
  sitlnet::tapbridge::ControlClient client(sitlnet::tapbridge::ControlSocketPath(scenario));
  sitlnet::proto::MediumRequest request;
  request.mutable_get_counters();
  sitlnet::proto::MediumResponse response;
  response.ParseFromString(client.Call(request.SerializeAsString()));
  return response.status();
}

Sample RunOnce(const Options& options, const sitlnet::Scenario& scenario,
               const std::vector<int>& fds, bool relay) {
  int err_pipe[2];
  pipe(err_pipe);
  const pid_t pid = fork();
  if (pid == 0) {
    dup2(err_pipe[1], 2);
    close(err_pipe[0]);
    std::vector<const char*> argv = {options.sitlnet.c_str(), "medium",
                                     scenario.source_path.c_str()};
    if (relay) argv.push_back("--relay");
    argv.push_back("--spin-us");
    argv.push_back(options.spin_us.c_str());
    argv.push_back(nullptr);
    execv(argv[0], const_cast<char* const*>(argv.data()));
    _exit(127);
  }
  close(err_pipe[1]);
  // Wait for the daemon's "attached" line (synchronize on output).
  std::string err;
  char buffer[4096];
  while (err.find("robots attached") == std::string::npos) {
    const ssize_t n = read(err_pipe[0], buffer, sizeof buffer);
    if (n <= 0) throw sitlnet::Error("medium daemon failed: " + err);
    err.append(buffer, n);
  }
  std::atomic<bool> stop{false};
  std::thread sender(Offer, std::cref(fds), options.offered_mbps, std::cref(stop));
  // Warm-up one second (queues fill), then measure.
  timespec warm{1, 0};
  nanosleep(&warm, nullptr);
  const sitlnet::proto::MediumStatus before = Status(scenario.name);
  const TimeNs cpu0 = ProcessCpuNs(pid), wall0 = sitlnet::MonotonicNowNs();
  timespec window{options.seconds, 0};
  nanosleep(&window, nullptr);
  const TimeNs cpu1 = ProcessCpuNs(pid), wall1 = sitlnet::MonotonicNowNs();
  const sitlnet::proto::MediumStatus after = Status(scenario.name);
  stop = true;
  sender.join();
  kill(pid, SIGTERM);
  waitpid(pid, nullptr, 0);
  close(err_pipe[0]);
  Sample s;
  s.cpu_percent = 100.0 * (cpu1 - cpu0) / (wall1 - wall0);
  s.p50_us = after.lateness_p50_ns() / 1e3;
  s.p99_us = after.lateness_p99_ns() / 1e3;
  s.delivered_per_s = (after.deliveries() - before.deliveries()) * 1e9 / (wall1 - wall0);
  return s;
}

double Median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string arg = argv[i];
    if (arg == "--robots")
      options.robots = std::stoi(argv[i + 1]);
    else if (arg == "--seconds")
      options.seconds = std::stoi(argv[i + 1]);
    else if (arg == "--repeat")
      options.repeat = std::stoi(argv[i + 1]);
    else if (arg == "--offered-mbps")
      options.offered_mbps = std::stod(argv[i + 1]);
    else if (arg == "--sitlnet")
      options.sitlnet = argv[i + 1];
  }
  if (geteuid() != 0) {
    std::fprintf(stderr, "tapbridge_bench: needs root (namespaces, TAPs)\n");
    return 2;
  }
  // 64 robots on an 8 x 8 grid, 1 m apart: all in range of each other at 54 Mb/s.
  const std::string name = "tbb" + std::to_string(getpid() % 100000);
  std::ostringstream text;
  text << "name: \"" << name << "\"\n";
  for (int i = 0; i < options.robots; ++i) {
    text << "robot { name: \"r" << i << "\" position_m { x: " << i % 8 << " y: " << i / 8
         << " z: 1 } }\n";
  }
  text << "radio { standard: STANDARD_80211A rate_mbps: 54 }\n"
       << "addresses { wlan_subnet: \"10.236.0.0/24\" ctl_subnet: \"10.237.0.0/16\" }\n";
  const std::string path = "/tmp/" + name + ".textproto";
  std::ofstream(path) << text.str();
  const sitlnet::Scenario scenario = sitlnet::LoadScenarioFile(path);
  sitlnet::nns::Up(scenario);
  int status = 0;
  try {
    const std::vector<int> fds = OpenSenders(scenario);
    std::printf(
        "%d robots, %.0f Mb/s offered (1512-byte frames, ring unicast), %d s windows, "
        "%d repetitions, medians\n",
        options.robots, options.offered_mbps, options.seconds, options.repeat);
    std::printf(
        "| configuration | daemon CPU (%% of a core) | lateness p50 (us) | p99 (us) | "
        "deliveries/s |\n| --- | --- | --- | --- | --- |\n");
    for (bool relay : {false, true}) {
      std::vector<double> cpu, p50, p99, rate;
      for (int r = 0; r < options.repeat; ++r) {
        const Sample s = RunOnce(options, scenario, fds, relay);
        cpu.push_back(s.cpu_percent);
        p50.push_back(s.p50_us);
        p99.push_back(s.p99_us);
        rate.push_back(s.delivered_per_s);
      }
      std::printf("| %s | %.1f | %.0f | %.0f | %.0f |\n",
                  relay ? "relay (no medium, floor)" : "medium (802.11a 54 Mb/s)", Median(cpu),
                  Median(p50), Median(p99), Median(rate));
      std::fflush(stdout);
    }
    for (int fd : fds) close(fd);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "tapbridge_bench: %s\n", e.what());
    status = 1;
  }
  sitlnet::nns::Down(name);
  unlink(path.c_str());
  return status;
}
