#include "tests/integration/nns_test_util.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <linux/capability.h>
#include <net/if.h>
#include <netinet/in.h>
#include <poll.h>
#include <sched.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <thread>

namespace sitlnet::nns::testing {
namespace {

std::vector<char*> CStrings(const std::vector<std::string>& strings) {
  std::vector<char*> result;
  for (const std::string& s : strings) result.push_back(const_cast<char*>(s.c_str()));
  result.push_back(nullptr);
  return result;
}

int DecodeStatus(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

std::string Base36(unsigned value) {
  std::string text;
  do {
    text.insert(text.begin(), "0123456789abcdefghijklmnopqrstuvwxyz"[value % 36]);
    value /= 36;
  } while (value != 0);
  return text;
}

}  // namespace

std::string ReadAll(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

std::string TempDir() {
  const char* tmp = std::getenv("TMPDIR");
  return std::string(tmp ? tmp : "/tmp");
}

bool IsCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

TestScenario MakeScenario(const std::string& tag, int slot, int robots,
                          const std::string& addresses_text, const std::string& extra_text) {
  // name <= 10 chars: 'n' + tag (<= 3) + pid in base 36 (<= 5) + slot.
  const unsigned pid = static_cast<unsigned>(getpid());
  std::string name = "n";
  name.append(tag.substr(0, 3)).append(Base36(pid)).append(std::to_string(slot));
  // 10.{210..219}/10.{230..239}.<pid%250>.0/24: away from the 10.77/10.78
  // defaults other runs use, distinct per slot and (mostly) per process.
  const std::string third = std::to_string(pid % 250);
  std::string text = "name: \"" + name + "\"\n";
  for (int i = 0; i < robots; ++i) text += "robot { name: \"r" + std::to_string(i + 1) + "\" }\n";
  text += "addresses { wlan_subnet: \"10." + std::to_string(230 + slot) + "." + third +
          ".0/24\" ctl_subnet: \"10." + std::to_string(210 + slot) + "." + third + ".0/24\" " +
          addresses_text + " }\n" + extra_text;
  const char* tmp = std::getenv("TMPDIR");
  const std::string path = std::string(tmp ? tmp : "/tmp") + "/" + name + ".textproto";
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

CommandResult RunCommand(const std::vector<std::string>& argv, TimeNs timeout_ns,
                         const std::vector<std::string>& env) {
  Child child(argv, env);
  CommandResult result;
  result.exit_code = child.Wait(timeout_ns);
  result.out = child.out();
  result.err = child.err();
  return result;
}

Child::Child(const std::vector<std::string>& argv, const std::vector<std::string>& env) {
  int out[2], err[2];
  SITLNET_DEMAND(pipe2(out, O_CLOEXEC) == 0 && pipe2(err, O_CLOEXEC) == 0);
  pid_ = fork();
  SITLNET_DEMAND(pid_ >= 0);
  if (pid_ == 0) {
    dup2(out[1], 1);
    dup2(err[1], 2);
    const int null = open("/dev/null", O_RDONLY);
    dup2(null, 0);
    for (const std::string& entry : env) putenv(const_cast<char*>(entry.c_str()));
    std::vector<char*> args = CStrings(argv);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(out[1]);
  close(err[1]);
  out_fd_ = out[0];
  err_fd_ = err[0];
  fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  fcntl(err_fd_, F_SETFL, O_NONBLOCK);
  pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, pid_, 0));
}

Child::~Child() {
  if (status_ < 0 && pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  for (int fd : {out_fd_, err_fd_, pidfd_}) {
    if (fd >= 0) close(fd);
  }
}

void Child::Drain(TimeNs timeout_ns, bool wake_on_exit) {
  pollfd fds[3] = {
      {out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}, {wake_on_exit ? pidfd_ : -1, POLLIN, 0}};
  if (poll(fds, 3, static_cast<int>(timeout_ns / kNsPerMs)) <= 0) return;
  char buffer[4096];
  for (int i = 0; i < 2; ++i) {
    if (fds[i].revents == 0) continue;
    int& fd = i == 0 ? out_fd_ : err_fd_;
    for (;;) {
      const ssize_t n = read(fd, buffer, sizeof buffer);
      if (n > 0) {
        (i == 0 ? out_ : err_).append(buffer, n);
        continue;
      }
      if (n == 0) {  // EOF: stop polling it.
        close(fd);
        fd = -1;
      }
      break;
    }
  }
}

bool Child::WaitForOutput(bool from_stderr, const std::string& needle, TimeNs timeout_ns) {
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  const std::string& text = from_stderr ? err_ : out_;
  while (text.find(needle) == std::string::npos) {
    const TimeNs left = deadline - MonotonicNowNs();
    if (left <= 0 || (from_stderr ? err_fd_ : out_fd_) < 0) return false;
    Drain(left, false);
  }
  return true;
}

int Child::Wait(TimeNs timeout_ns) {
  if (status_ >= 0) return DecodeStatus(status_);
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  for (;;) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      status_ = status;
      Drain(0, false);  // What the child wrote before exiting.
      return DecodeStatus(status);
    }
    const TimeNs left = deadline - MonotonicNowNs();
    if (left <= 0) break;
    Drain(left, true);  // Wakes on output or on exit (pidfd).
  }
  kill(pid_, SIGKILL);
  int status = 0;
  waitpid(pid_, &status, 0);
  status_ = status;
  return -1;
}

bool HasCapability(int cap) {
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3]{};
  if (syscall(SYS_capget, &header, data) != 0) return false;
  return (data[cap / 32].effective & (1u << (cap % 32))) != 0;
}

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

std::string UdpRoundTrip(const std::string& netns, Ipv4 robot_address) {
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
  const int root_fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
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
      error = "no echo back in the root namespace";
    } else if (recv(root_fd, buffer, sizeof buffer, 0) != static_cast<ssize_t>(sizeof ping)) {
      error = "echo has the wrong size";
    }
  }
  close(root_fd);
  close(echo_fd);
  return error;
}

std::string SitlnetBinary() {
  if (const char* dir = std::getenv("SITLNET_BINARY_DIR")) return std::string(dir) + "/bin/sitlnet";
  // Run by hand: this binary is <build>/tests/<name>.
  char self[4096] = {};
  const ssize_t n = readlink("/proc/self/exe", self, sizeof self - 1);
  std::string path(self, n > 0 ? n : 0);
  path = path.substr(0, path.rfind('/'));
  return path.substr(0, path.rfind('/')) + "/bin/sitlnet";
}

bool LinkExistsInRoot(const std::string& name) { return if_nametoindex(name.c_str()) != 0; }

bool StateExists(const std::string& scenario) {
  struct stat st {};
  return stat((std::string(kStateDir) + "/" + scenario).c_str(), &st) == 0;
}

}  // namespace sitlnet::nns::testing
