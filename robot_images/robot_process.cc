// Robot processes: `sitlnet exec` of an image, logged, stopped by pid.
#include <fcntl.h>
#include <linux/capability.h>
#include <poll.h>
#include <pwd.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "robot_images/robot_images.h"

namespace sitlnet::images {
namespace {

int ShellStatus(int wait_status) {
  if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
  if (WIFSIGNALED(wait_status)) return 128 + WTERMSIG(wait_status);
  return 255;
}

}  // namespace

RobotProcess::RobotProcess(const Image& image, const LaunchContext& context,
                           const std::string& sitlnet_exe, const std::string& log_path)
    : robot_(context.robot), log_path_(log_path), ready_line_(image.manifest.ready_log_line()) {
  std::vector<std::string> args = {sitlnet_exe,      "exec",        "--scenario",
                                   context.scenario, context.robot, "--"};
  if (!image.manifest.user().empty()) {
    // util-linux's setpriv drops to the user inside the namespace, unmodified. The group is
    // the user's primary group by number: Debian's "nobody" has group "nogroup", so
    // --regid=<user name> fails there.
    const passwd* user = getpwnam(image.manifest.user().c_str());
    if (user == nullptr) {
      throw Error("robot \"" + robot_ + "\": image user \"" + image.manifest.user() +
                  "\" does not exist on this host (" + image.manifest_path + ")");
    }
    // Checked here rather than left to setpriv, whose "setresuid failed" would only reach the
    // robot's log (docs/security.md: a run under only CAP_NET_ADMIN + CAP_SYS_ADMIN).
    if (!HasEffectiveCapability(CAP_SETUID) || !HasEffectiveCapability(CAP_SETGID)) {
      throw Error("robot \"" + robot_ + "\": image user \"" + image.manifest.user() + "\" (" +
                  image.manifest_path +
                  ") needs CAP_SETUID and CAP_SETGID to switch user: run as root, or remove "
                  "`user` from the manifest");
    }
    for (const char* arg : {"setpriv", "--init-groups", "--reset-env"}) args.push_back(arg);
    args.push_back("--reuid=" + std::to_string(user->pw_uid));
    args.push_back("--regid=" + std::to_string(user->pw_gid));
    args.push_back("--");
  }
  const std::vector<std::string> command = ExpandCommand(image, context);
  args.insert(args.end(), command.begin(), command.end());
  const std::vector<std::string> env = ExpandEnv(image, context);

  const int log_fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd < 0)
    throw Error(SystemErrorMessage("robot \"" + robot_ + "\": open log " + log_path, errno));
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);

  pid_ = fork();
  if (pid_ < 0) {
    const int err = errno;
    close(log_fd);
    throw Error(SystemErrorMessage("robot \"" + robot_ + "\": fork", err));
  }
  if (pid_ == 0) {
    // Own session: a Ctrl-C on the terminal reaches `sitlnet run`, which stops
    // the robots in order, not every robot at once.
    setsid();
    // `sitlnet run` may hold SCHED_FIFO in realtime pacing; the robot's software runs as on
    // any host, at normal priority (wrap its command in chrt to change that).
    ResetToNormalScheduling();
    dup2(log_fd, STDOUT_FILENO);
    dup2(log_fd, STDERR_FILENO);
    const int null_fd = open("/dev/null", O_RDONLY);
    if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
    for (const std::string& variable : env) putenv(const_cast<char*>(variable.c_str()));
    execv(argv[0], argv.data());
    dprintf(STDERR_FILENO, "sitlnet: robot \"%s\": run %s: %s\n", robot_.c_str(), argv[0],
            std::strerror(errno));
    _exit(127);
  }
  close(log_fd);
  pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, pid_, 0));
}

RobotProcess::~RobotProcess() {
  Stop();
  if (pidfd_ >= 0) close(pidfd_);
}

std::optional<int> RobotProcess::PollExit() {
  if (exit_status_ || pid_ <= 0) return exit_status_;
  int status = 0;
  const pid_t done = waitpid(pid_, &status, WNOHANG);
  if (done == pid_) exit_status_ = ShellStatus(status);
  return exit_status_;
}

std::optional<int> RobotProcess::WaitExit(TimeNs timeout_ns) {
  if (PollExit() || pidfd_ < 0) return exit_status_;
  pollfd wait{pidfd_, POLLIN, 0};
  poll(&wait, 1, static_cast<int>(timeout_ns / kNsPerMs));
  return PollExit();
}

bool RobotProcess::IsReady() const {
  if (ready_line_.empty()) return true;
  std::ifstream log(log_path_);
  std::ostringstream text;
  text << log.rdbuf();
  return text.str().find(ready_line_) != std::string::npos;
}

void RobotProcess::Stop(TimeNs grace_ns) {
  if (pid_ <= 0 || PollExit()) return;
  kill(pid_, SIGTERM);
  if (!WaitExit(grace_ns)) kill(pid_, SIGKILL);
  int status = 0;
  if (!exit_status_ && waitpid(pid_, &status, 0) == pid_) exit_status_ = ShellStatus(status);
}

}  // namespace sitlnet::images
