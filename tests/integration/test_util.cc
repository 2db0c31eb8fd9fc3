#include "tests/integration/test_util.h"

#include <fcntl.h>
#include <linux/capability.h>
#include <poll.h>
#include <signal.h>
#include <sys/inotify.h>
#include <sys/prctl.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

namespace sitlnet::integration_test {
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

bool EnvIs(const char* name, const std::string& value) {
  const char* set = std::getenv(name);
  return set != nullptr && value == set;
}

}  // namespace

bool IsCi() { return EnvIs("CI", "true"); }

bool IsMinCapsPass() { return EnvIs("SITLNET_MIN_CAPS", "1"); }

bool HasCapability(int cap) { return HasEffectiveCapability(cap); }

Child::Child(const std::vector<std::string>& argv, const std::vector<std::string>& env,
             const std::function<void()>& before_exec) {
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
    if (before_exec) before_exec();
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
  char buffer[65536];
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

int Child::Poll() {
  if (status_ >= 0) return DecodeStatus(status_);
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) != pid_) return -1;
  status_ = status;
  Drain(0, false);  // What the child wrote before exiting.
  return DecodeStatus(status);
}

int Child::Wait(TimeNs timeout_ns) {
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  for (;;) {
    const int code = Poll();
    if (code >= 0 || status_ >= 0) return code;
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

CommandResult RunCommand(const std::vector<std::string>& argv, TimeNs timeout_ns,
                         const std::vector<std::string>& env) {
  Child child(argv, env);
  CommandResult result;
  result.exit_code = child.Wait(timeout_ns);
  result.out = child.out();
  result.err = child.err();
  return result;
}

CommandResult RunWithoutCapabilities(const std::vector<std::string>& argv, uint64_t drop_mask,
                                     TimeNs timeout_ns) {
  // Read before fork: the child only makes system calls.
  __user_cap_header_struct header{_LINUX_CAPABILITY_VERSION_3, 0};
  __user_cap_data_struct data[_LINUX_CAPABILITY_U32S_3]{};
  SITLNET_DEMAND(syscall(SYS_capget, &header, data) == 0);
  for (int i = 0; i < _LINUX_CAPABILITY_U32S_3; ++i) {
    const auto keep = static_cast<uint32_t>(~(drop_mask >> (32 * i)));
    data[i].effective &= keep;
    data[i].permitted &= keep;
    data[i].inheritable &= keep;
  }
  Child child(argv, {}, [&] {
    if (prctl(PR_SET_NO_NEW_PRIVS, 1, 0, 0, 0) != 0 || syscall(SYS_capset, &header, data) != 0) {
      _exit(126);
    }
  });
  CommandResult result;
  result.exit_code = child.Wait(timeout_ns);
  result.out = child.out();
  result.err = child.err();
  return result;
}

std::string ReadAll(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

namespace {

// The first line of /proc/stat: jiffies of all CPUs by state (user nice system idle iowait irq
// softirq steal).
struct CpuJiffies {
  unsigned long long busy = 0, idle = 0, stolen = 0;
};

CpuJiffies ReadCpuJiffies() {
  unsigned long long user = 0, nice = 0, system = 0, idle = 0, iowait = 0, irq = 0, softirq = 0,
                     steal = 0;
  const std::string stat = ReadAll("/proc/stat");
  std::sscanf(stat.c_str(), "cpu %llu %llu %llu %llu %llu %llu %llu %llu", &user, &nice, &system,
              &idle, &iowait, &irq, &softirq, &steal);
  return {user + nice + system + irq + softirq, idle + iowait, steal};
}

// Made when the test process starts: ctest runs one test per process, so the shares since then
// are the test's.
const HostCpuWatch kSinceProcessStart;

}  // namespace

HostCpuWatch::HostCpuWatch() {
  const CpuJiffies now = ReadCpuJiffies();
  busy_ = now.busy;
  idle_ = now.idle;
  stolen_ = now.stolen;
}

HostCpuWatch::Shares HostCpuWatch::SharesUpToNow() const {
  const CpuJiffies now = ReadCpuJiffies();
  const double total =
      static_cast<double>((now.busy - busy_) + (now.idle - idle_) + (now.stolen - stolen_));
  if (total <= 0) return {};
  return {static_cast<double>(now.busy - busy_) / total,
          static_cast<double>(now.stolen - stolen_) / total};
}

std::string HostLoad(const HostCpuWatch* since) {
  double one = 0, five = 0, fifteen = 0;
  const std::string loadavg = ReadAll("/proc/loadavg");
  std::sscanf(loadavg.c_str(), "%lf %lf %lf", &one, &five, &fifteen);
  const HostCpuWatch::Shares shares = (since ? *since : kSinceProcessStart).SharesUpToNow();
  char line[192];
  std::snprintf(line, sizeof line,
                "host load average %.2f, %.2f, %.2f on %u cores; since the test began the CPUs "
                "were %.0f %% busy, %.0f %% stolen by the hypervisor",
                one, five, fifteen, std::thread::hardware_concurrency(), 100 * shares.busy,
                100 * shares.stolen);
  return line;
}

std::string WithoutLines(const std::string& text, const std::vector<std::string>& prefixes) {
  std::string kept;
  size_t left_out = 0;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    const bool drop = std::any_of(prefixes.begin(), prefixes.end(),
                                  [&](const std::string& p) { return line.rfind(p, 0) == 0; });
    if (drop) {
      ++left_out;
    } else {
      kept += line + "\n";
    }
  }
  return kept + "(" + std::to_string(left_out) + " lines left out)\n";
}

std::string TempDir() {
  // One private folder per test process, removed with everything in it when the process
  // exits normally, so scenario files and run folders do not pile up in /tmp.
  struct Folder {
    std::string path;
    Folder() {
      const char* tmp = std::getenv("TMPDIR");
      std::string pattern = std::string(tmp ? tmp : "/tmp") + "/sitlnet-test-XXXXXX";
      SITLNET_DEMAND(mkdtemp(pattern.data()) != nullptr);
      // World-readable like /tmp's entries: images may run as another user (`user: nobody`).
      SITLNET_DEMAND(chmod(pattern.c_str(), 0755) == 0);
      path = pattern;
    }
    ~Folder() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Folder folder;
  return folder.path;
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

std::string SourceDir() {
  const char* dir = std::getenv("SITLNET_SOURCE_DIR");
  return dir ? dir : ".";
}

SetupVerdict AskSetup(const std::string& group) {
  const CommandResult check =
      RunCommand({SourceDir() + "/scripts/setup", "--check", group}, 120 * kNsPerS);
  SetupVerdict verdict;
  verdict.for_this_machine = check.exit_code != 77;
  verdict.line = check.out + check.err;
  while (!verdict.line.empty() && verdict.line.back() == '\n') verdict.line.pop_back();
  if (verdict.line.empty()) verdict.line = "scripts/setup --check " + group + " said nothing";
  return verdict;
}

std::string Base36(unsigned value) {
  std::string text;
  do {
    text.insert(text.begin(), "0123456789abcdefghijklmnopqrstuvwxyz"[value % 36]);
    value /= 36;
  } while (value != 0);
  return text;
}

std::string PingProgram() {
  if (prctl(PR_CAPBSET_READ, CAP_NET_RAW, 0, 0, 0) == 1) return "ping";
  return PingWithoutFileCapabilities();
}

std::string PingWithoutFileCapabilities() {
  // A plain copy of the bytes carries no security.capability attribute.
  static const struct Copy {
    std::string dir = TempDir() + "/sitlnet-ping-" + std::to_string(getpid());
    std::string path = dir + "/ping";
    Copy() {
      SITLNET_DEMAND(mkdir(dir.c_str(), 0755) == 0 || errno == EEXIST);
      std::ofstream(path, std::ios::binary) << ReadAll("/usr/bin/ping");
      SITLNET_DEMAND(chmod(path.c_str(), 0755) == 0);
    }
    ~Copy() {
      unlink(path.c_str());
      rmdir(dir.c_str());
    }
  } copy;
  return copy.path;
}

bool WaitForFiles(const std::string& dir, const std::function<bool()>& done, TimeNs timeout_ns) {
  const int fd = inotify_init1(IN_CLOEXEC | IN_NONBLOCK);
  inotify_add_watch(fd, dir.c_str(), IN_MODIFY | IN_CREATE | IN_CLOSE_WRITE);
  const TimeNs deadline = MonotonicNowNs() + timeout_ns;
  bool ok = done();
  while (!ok && MonotonicNowNs() < deadline) {
    pollfd p{fd, POLLIN, 0};
    // The timeout only bounds a missed event (files created before the watch).
    if (poll(&p, 1, 200) > 0) {
      char buffer[4096];
      while (read(fd, buffer, sizeof buffer) > 0) {
      }
    }
    ok = done();
  }
  close(fd);
  return ok;
}

}  // namespace sitlnet::integration_test
