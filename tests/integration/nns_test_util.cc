#include "tests/integration/nns_test_util.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <net/if.h>
#include <netinet/in.h>
#include <poll.h>
#include <sched.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <thread>

namespace sitlnet::nns::testing {
TestScenario MakeScenario(const std::string& tag, int slot, int robots,
                          const std::string& addresses_text, const std::string& extra_text) {
  // name <= 10 chars: 'n' + tag (<= 3) + pid in base 36 (<= 5) + slot.
  const unsigned pid = static_cast<unsigned>(getpid());
  std::string name = "n";
  name.append(tag.substr(0, 3)).append(integration_test::Base36(pid)).append(std::to_string(slot));
  // 10.{210..219}/10.{230..239}.<pid%250>.0/24: away from the 10.77/10.78
  // defaults other runs use, distinct per slot and (mostly) per process.
  const std::string third = std::to_string(pid % 250);
  std::string text = "name: \"" + name + "\"\n";
  for (int i = 0; i < robots; ++i) text += "robot { name: \"r" + std::to_string(i + 1) + "\" }\n";
  text += "addresses { wlan_subnet: \"10." + std::to_string(230 + slot) + "." + third +
          ".0/24\" ctl_subnet: \"10." + std::to_string(210 + slot) + "." + third + ".0/24\" " +
          addresses_text + " }\n" + extra_text;
  const std::string path = TempDir() + "/" + name + ".textproto";
  std::ofstream(path) << text;
  // Removed when the test process exits.
  static struct Files {
    std::vector<std::string> paths;
    ~Files() {
      for (const std::string& p : paths) unlink(p.c_str());
    }
  } files;
  files.paths.push_back(path);
  return TestScenario{path, LoadScenarioFile(path)};
}

DownGuard::~DownGuard() {
  try {
    Down(name_);
  } catch (const std::exception& e) {
    ADD_FAILURE() << "cleanup of scenario " << name_ << " failed: " << e.what();
  }
}

CommandGuard::~CommandGuard() { RunCommand(command_); }

namespace {

sockaddr_in SocketAddress(Ipv4 address, uint16_t port) {
  sockaddr_in sa{};
  sa.sin_family = AF_INET;
  sa.sin_addr.s_addr = htonl(address.host_order);
  sa.sin_port = htons(port);
  return sa;
}

bool PollIn(int fd, TimeNs timeout_ns) {
  pollfd p{fd, POLLIN, 0};
  return poll(&p, 1, static_cast<int>(timeout_ns / kNsPerMs)) == 1;
}

}  // namespace

std::string UdpRoundTrip(const std::string& scenario, const std::string& netns,
                         Ipv4 robot_address) {
  constexpr uint16_t kPort = 47999;
  const TimeNs timeout_ns = 5 * kNsPerS;
  // The echo socket is created by a thread inside the robot: setns moves only
  // that thread, and the socket stays in the robot's namespace.
  int echo_fd = -1;
  std::string error;
  std::thread inside([&] {
    const int ns = open(NetnsPath(netns).c_str(), O_RDONLY | O_CLOEXEC);
    if (ns < 0 || setns(ns, CLONE_NEWNET) != 0) {
      error = "enter " + netns + ": " + std::strerror(errno);
      if (ns >= 0) close(ns);
      return;
    }
    close(ns);
    echo_fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    const sockaddr_in local = SocketAddress(robot_address, kPort);
    if (bind(echo_fd, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
      error = "bind inside " + netns + ": " + std::strerror(errno);
    }
  });
  inside.join();  // The thread ends; its socket lives on.
  if (!error.empty()) return error;
  int root_fd = -1;
  {
    // The root side of ctl0 is in the scenario's ctl namespace.
    ScopedNetns in_ctl(CtlNetnsName(scenario));
    root_fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  }
  const sockaddr_in to = SocketAddress(robot_address, kPort);
  const char ping[] = "sitlnet-udp-ping";
  if (sendto(root_fd, ping, sizeof ping, 0, reinterpret_cast<const sockaddr*>(&to), sizeof to) !=
      static_cast<ssize_t>(sizeof ping)) {
    error = std::string("send to robot: ") + std::strerror(errno);
  } else if (!PollIn(echo_fd, timeout_ns)) {
    error = "nothing arrived inside the robot";
  } else {
    char buffer[64];
    sockaddr_in from{};
    socklen_t from_length = sizeof from;
    const ssize_t n = recvfrom(echo_fd, buffer, sizeof buffer, 0,
                               reinterpret_cast<sockaddr*>(&from), &from_length);
    sendto(echo_fd, buffer, n, 0, reinterpret_cast<const sockaddr*>(&from), from_length);
    if (!PollIn(root_fd, timeout_ns)) {
      error = "no echo back in the ctl namespace";
    } else if (recv(root_fd, buffer, sizeof buffer, 0) != static_cast<ssize_t>(sizeof ping)) {
      error = "echo has the wrong size";
    }
  }
  close(root_fd);
  close(echo_fd);
  return error;
}

bool LinkExistsInRoot(const std::string& name) { return if_nametoindex(name.c_str()) != 0; }

bool LinkExistsInCtl(const std::string& scenario, const std::string& name) {
  if (!NetnsExists(CtlNetnsName(scenario))) return false;
  ScopedNetns in_ctl(CtlNetnsName(scenario));
  return if_nametoindex(name.c_str()) != 0;
}

bool StateExists(const std::string& scenario) {
  struct stat st {};
  return stat((std::string(kStateDir) + "/" + scenario).c_str(), &st) == 0;
}

std::string WriteImageManifest(const std::string& name, const std::string& body) {
  const std::string path = TempDir() + "/image_" + name + ".textproto";
  std::ofstream(path) << "name: \"" << name << "\"\n" << body;
  return path;
}

}  // namespace sitlnet::nns::testing
