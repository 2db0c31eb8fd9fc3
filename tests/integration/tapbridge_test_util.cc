#include "tests/integration/tapbridge_test_util.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <fstream>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge::testing {

bool IsCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

std::string MissingRoot() {
  if (geteuid() != 0) return "needs root (namespaces, TAP devices): run with sudo";
  if (access("/dev/net/tun", R_OK | W_OK) != 0) return "needs read-write /dev/net/tun";
  return "";
}

Child::Child(const std::vector<std::string>& argv) {
  int out[2], err[2];
  SITLNET_DEMAND(pipe2(out, O_CLOEXEC) == 0 && pipe2(err, O_CLOEXEC) == 0);
  pid_ = fork();
  SITLNET_DEMAND(pid_ >= 0);
  if (pid_ == 0) {
    dup2(out[1], 1);
    dup2(err[1], 2);
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execvp(args[0], args.data());
    _exit(127);
  }
  close(out[1]);
  close(err[1]);
  out_fd_ = out[0];
  err_fd_ = err[0];
  fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  fcntl(err_fd_, F_SETFL, O_NONBLOCK);
}

Child::~Child() {
  if (status_ < 0 && pid_ > 0) {
    kill(pid_, SIGKILL);
    waitpid(pid_, nullptr, 0);
  }
  if (out_fd_ >= 0) close(out_fd_);
  if (err_fd_ >= 0) close(err_fd_);
}

void Child::Pump(TimeNs timeout_ns) {
  pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
  poll(fds, 2, static_cast<int>(std::max<TimeNs>(0, timeout_ns / kNsPerMs)));
  char buffer[65536];
  for (int i = 0; i < 2; ++i) {
    for (;;) {
      const ssize_t n = read(fds[i].fd, buffer, sizeof buffer);
      if (n <= 0) break;
      (i == 0 ? out_ : err_).append(buffer, n);
    }
  }
}

bool Child::WaitFor(const std::string& needle, bool in_stderr, TimeNs timeout_ns) {
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  for (;;) {
    if ((in_stderr ? err_ : out_).find(needle) != std::string::npos) return true;
    const TimeNs left = deadline - MonotonicNowNs();
    if (left <= 0) return false;
    if (status_ < 0) {
      int status = 0;
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        Pump(0);
        return (in_stderr ? err_ : out_).find(needle) != std::string::npos;
      }
    }
    Pump(std::min<TimeNs>(left, 50 * kNsPerMs));  // Poll timeout: wakes on output.
  }
}

int Child::Wait(TimeNs timeout_ns) {
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  while (status_ < 0) {
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      status_ = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
      break;
    }
    if (MonotonicNowNs() > deadline) return -1;
    Pump(20 * kNsPerMs);
  }
  Pump(0);
  return status_;
}

Result RunProgram(const std::vector<std::string>& argv, TimeNs timeout_ns) {
  Child child(argv);
  Result result;
  result.code = child.Wait(timeout_ns);
  result.out = child.out();
  result.err = child.err();
  return result;
}

std::string SitlnetBinary() {
  const char* dir = std::getenv("SITLNET_BINARY_DIR");
  return std::string(dir ? dir : ".") + "/bin/sitlnet";
}

std::string SourceDir() {
  const char* dir = std::getenv("SITLNET_SOURCE_DIR");
  return dir ? dir : ".";
}

MediumScenario::MediumScenario(const std::string& tag, int slot, const std::string& body,
                               const std::string& address_extra) {
  const unsigned pid = static_cast<unsigned>(getpid());
  std::string base36;
  for (unsigned v = pid; v != 0 || base36.empty(); v /= 36) {
    base36.insert(base36.begin(), "0123456789abcdefghijklmnopqrstuvwxyz"[v % 36]);
  }
  name_ = "t" + tag.substr(0, 3) + base36 + std::to_string(slot);
  // 10.{240..244} / 10.{250..254}: away from the defaults and other modules' tests.
  const std::string third = std::to_string(pid % 250);
  subnet_prefix_ = "10." + std::to_string(240 + slot) + "." + third + ".";
  const char* tmp = std::getenv("TMPDIR");
  dir_ = std::string(tmp ? tmp : "/tmp") + "/" + name_;
  RunProgram({"mkdir", "-p", dir_});
  path_ = dir_ + "/" + name_ + ".textproto";
  std::ofstream(path_) << "name: \"" << name_ << "\"\n"
                       << body << "\naddresses { wlan_subnet: \"" << subnet_prefix_
                       << "0/24\" ctl_subnet: \"10." << 250 + slot << "." << third << ".0/24\" "
                       << address_extra << " }\n";
  const Result up = RunProgram({SitlnetBinary(), "up", path_});
  up_ = true;  // Down also after a partial failure.
  if (up.code != 0) ADD_FAILURE() << "sitlnet up " << path_ << ": " << up.err;
}

MediumScenario::~MediumScenario() {
  if (daemon_) StopDaemon();
  if (up_) {
    const Result down = RunProgram({SitlnetBinary(), "down", name_});
    if (down.code != 0) ADD_FAILURE() << "sitlnet down " << name_ << ": " << down.err;
  }
}

std::string MediumScenario::Address(int index) const {
  return subnet_prefix_ + std::to_string(index + 1);
}

void MediumScenario::StartDaemon(const std::vector<std::string>& args) {
  std::vector<std::string> argv = {SitlnetBinary(), "medium", path_};
  argv.insert(argv.end(), args.begin(), args.end());
  daemon_ = std::make_unique<Child>(argv);
  ASSERT_TRUE(daemon_->WaitFor("robots attached", true, 10 * kNsPerS)) << daemon_->err();
}

std::string MediumScenario::StopDaemon() {
  if (!daemon_) return "";
  kill(daemon_->pid(), SIGTERM);
  const int code = daemon_->Wait(10 * kNsPerS);
  EXPECT_EQ(code, 0) << "medium daemon exit: " << daemon_->err();
  std::string err = daemon_->err();
  daemon_.reset();
  return err;
}

Result MediumScenario::Exec(const std::string& robot, const std::vector<std::string>& argv,
                            TimeNs timeout_ns) {
  std::vector<std::string> full = {SitlnetBinary(), "exec", Netns(robot), "--"};
  full.insert(full.end(), argv.begin(), argv.end());
  return RunProgram(full, timeout_ns);
}

std::unique_ptr<Child> MediumScenario::Spawn(const std::string& robot,
                                             const std::vector<std::string>& argv) {
  std::vector<std::string> full = {SitlnetBinary(), "exec", Netns(robot), "--"};
  full.insert(full.end(), argv.begin(), argv.end());
  return std::make_unique<Child>(full);
}

proto::MediumStatus MediumScenario::Counters() {
  ControlClient client(ControlSocketPath(name_));
  proto::MediumRequest request;
  request.mutable_get_counters();
  proto::MediumResponse response;
  EXPECT_TRUE(response.ParseFromString(client.Call(request.SerializeAsString())));
  EXPECT_FALSE(response.has_error()) << response.error();
  return response.status();
}

void MediumScenario::SetPosition(const std::string& robot, double x, double y, double z) {
  ControlClient client(ControlSocketPath(name_));
  proto::MediumRequest request;
  proto::RobotPosition* p = request.mutable_set_positions()->add_position();
  p->set_robot(robot);
  p->mutable_position_m()->set_x(x);
  p->mutable_position_m()->set_y(y);
  p->mutable_position_m()->set_z(z);
  proto::MediumResponse response;
  EXPECT_TRUE(response.ParseFromString(client.Call(request.SerializeAsString())));
  EXPECT_FALSE(response.has_error()) << response.error();
}

TimeNs OfdmAirtimeNs(int psdu_bytes, double rate_mbps) {
  const int bits_per_symbol = static_cast<int>(std::lround(4 * rate_mbps));
  const int symbols = (16 + 8 * psdu_bytes + 6 + bits_per_symbol - 1) / bits_per_symbol;
  return (20 + 4 * symbols) * kNsPerUs;
}

double OfdmAckRateMbps(double rate_mbps) {
  double best = 6;
  for (double basic : {6.0, 12.0, 24.0}) {
    if (basic <= rate_mbps) best = basic;
  }
  return best;
}

double OneStationGoodputMbps(int udp_payload_bytes, double rate_mbps) {
  const int ethernet_bytes = udp_payload_bytes + 8 + 20 + 14;  // UDP, IPv4, Ethernet headers
  const double cycle_ns = kOfdmDifsNs + kOfdmCwMin / 2.0 * kOfdmSlotNs +
                          OfdmAirtimeNs(ethernet_bytes + kEthernetToPsduBytes, rate_mbps) +
                          kOfdmSifsNs + OfdmAirtimeNs(kAckBytes, OfdmAckRateMbps(rate_mbps));
  return udp_payload_bytes * 8.0 / cycle_ns * 1e3;
}

}  // namespace sitlnet::tapbridge::testing
