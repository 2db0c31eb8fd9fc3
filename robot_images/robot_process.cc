// Robot processes: `sitlnet exec` of an image, logged, stopped by pid.
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>

#include "robot_images/images_internal.h"
#include "robot_images/robot_images.h"

namespace sitlnet::images {
namespace {

int ShellStatus(int wait_status) {
  if (WIFEXITED(wait_status)) return WEXITSTATUS(wait_status);
  if (WIFSIGNALED(wait_status)) return 128 + WTERMSIG(wait_status);
  return 255;
}

// The first pid listed in /proc/PID/task/PID/children, or -1.
pid_t FirstChild(pid_t pid) {
  const std::string path =
      "/proc/" + std::to_string(pid) + "/task/" + std::to_string(pid) + "/children";
  std::ifstream children(path);
  pid_t child = -1;
  if (!(children >> child)) return -1;
  return child;
}

}  // namespace

RobotProcess::RobotProcess(const Image& image, const LaunchContext& context,
                           const std::string& sitlnet_exe, const std::string& log_path)
    : robot_(context.robot),
      log_path_(log_path),
      ready_line_(image.manifest.ready_log_line()),
      container_(ContainerTargetOf(image, context)) {
  // A container is confined by its engine, not by bubblewrap.
  sandboxed_ = !container_ && image.manifest.sandbox() == proto::ImageManifest::CONFINED;
  std::vector<std::string> args = {sitlnet_exe,      "exec",        "--scenario",
                                   context.scenario, context.robot, "--"};
  const std::vector<std::string> command = ExpandCommand(image, context);
  std::vector<std::string> env = ExpandEnv(image, context);
  if (container_) {
    args = internal::ContainerRunArgs(image, context, *container_, command, env);
    env.clear();  // In the container (--env), not in podman's own environment.
  } else {
    // Only for the image's command: in the sandbox bubblewrap sets it, so that sitlnet exec and
    // bubblewrap run on the host's clock and keep no libfaketime state in the host's /dev/shm.
    std::vector<std::string> time_env = internal::DilatedTimeEnvironment(image, context, command);
    if (!sandboxed_) {
      env.insert(env.end(), time_env.begin(), time_env.end());  // After the manifest's env.
      time_env.clear();
    }
    const std::vector<std::string> prefix = internal::ConfinementPrefix(image, context, time_env);
    args.insert(args.end(), prefix.begin(), prefix.end());
    args.insert(args.end(), command.begin(), command.end());
  }

  const int log_fd = open(log_path.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
  if (log_fd < 0)
    throw Error(SystemErrorMessage("robot \"" + robot_ + "\": open log " + log_path, errno));
  // bubblewrap writes the pid of the sandbox's init here (--info-fd), read in SandboxInit().
  int info_pipe[2] = {-1, -1};
  if (sandboxed_ && pipe2(info_pipe, O_CLOEXEC) != 0) {
    const int err = errno;
    close(log_fd);
    throw Error(SystemErrorMessage("robot \"" + robot_ + "\": pipe", err));
  }
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);

  pid_ = fork();
  if (pid_ < 0) {
    const int err = errno;
    close(log_fd);
    for (int fd : info_pipe) {
      if (fd >= 0) close(fd);
    }
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
    // Into the robot's cgroup before anything of the robot runs (after the scheduling reset: a
    // realtime process may not join a cgroup whose CPU is limited). A robot outside it would be
    // neither limited nor killed with it, so it does not start.
    for (int fd : context.cgroup_join_fds) {
      if (write(fd, "0", 1) != 1) {
        dprintf(STDERR_FILENO, "sitlnet: robot \"%s\": join its cgroup: %s\n", robot_.c_str(),
                std::strerror(errno));
        _exit(126);
      }
    }
    const int null_fd = open("/dev/null", O_RDONLY);
    if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
    // Inherited through `sitlnet exec` by bubblewrap and the command; dup2 clears close-on-exec,
    // except on the same number.
    const auto pass = [](int fd, int as) {
      if (fd == as) {
        fcntl(fd, F_SETFD, 0);
      } else {
        dup2(fd, as);
      }
    };
    // Moved above both numbers first, so that neither dup2 can overwrite the other's source.
    const int passed = context.passed_fd >= 0 ? fcntl(context.passed_fd, F_DUPFD, 16) : -1;
    if (sandboxed_) pass(info_pipe[1], internal::kSandboxInfoFd);
    if (passed >= 0) pass(passed, kPassedFd);
    for (const std::string& variable : env) putenv(const_cast<char*>(variable.c_str()));
    execv(argv[0], argv.data());
    dprintf(STDERR_FILENO, "sitlnet: robot \"%s\": run %s: %s\n", robot_.c_str(), argv[0],
            std::strerror(errno));
    _exit(127);
  }
  close(log_fd);
  if (sandboxed_) {
    close(info_pipe[1]);
    info_fd_ = info_pipe[0];
  }
  pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, pid_, 0));
}

RobotProcess::~RobotProcess() {
  Stop();
  for (int fd : {pidfd_, info_fd_, init_pidfd_}) {
    if (fd >= 0) close(fd);
  }
}

pid_t RobotProcess::SandboxInit() {
  if (info_fd_ >= 0) {
    // Blocks until bubblewrap has set the sandbox up (milliseconds), or reads EOF if it failed.
    init_pid_ = internal::ReadSandboxInitPid(info_fd_);
    close(info_fd_);
    info_fd_ = -1;
    if (init_pid_ > 0) init_pidfd_ = static_cast<int>(syscall(SYS_pidfd_open, init_pid_, 0));
  }
  return init_pid_;
}

void RobotProcess::WaitSandboxGone(TimeNs timeout_ns) {
  // bubblewrap exits as soon as the command has, while the sandbox's init may still be ending
  // the robot's other processes (killed with it, --die-with-parent). When the init has exited,
  // the kernel has reaped every process of its PID namespace.
  if (SandboxInit() <= 0 || init_pidfd_ < 0) return;
  pollfd gone{init_pidfd_, POLLIN, 0};
  poll(&gone, 1, static_cast<int>(timeout_ns / kNsPerMs));
  // Reaped here when this process is the subreaper it was reparented to (`sitlnet run`).
  if (gone.revents & POLLIN) waitpid(init_pid_, nullptr, WNOHANG);
}

std::optional<int> RobotProcess::PollExit() {
  if (exit_status_ || pid_ <= 0) return exit_status_;
  int status = 0;
  const pid_t done = waitpid(pid_, &status, WNOHANG);
  if (done == pid_) {
    exit_status_ = ShellStatus(status);
    WaitSandboxGone(0);  // Reaped if already gone; never waits here (the run's loop calls this).
  }
  return exit_status_;
}

std::optional<int> RobotProcess::WaitExit(TimeNs timeout_ns) {
  const TimeNs deadline_ns = MonotonicNowNs() + timeout_ns;
  if (!PollExit() && pidfd_ >= 0) {
    pollfd wait{pidfd_, POLLIN, 0};
    poll(&wait, 1, static_cast<int>(timeout_ns / kNsPerMs));
    PollExit();
  }
  // Exited: the rest of the robot's processes too, within what is left of the timeout.
  if (exit_status_) WaitSandboxGone(std::max<TimeNs>(0, deadline_ns - MonotonicNowNs()));
  return exit_status_;
}

bool RobotProcess::IsReady() const {
  if (ready_line_.empty()) return true;
  std::ifstream log(log_path_);
  std::ostringstream text;
  text << log.rdbuf();
  return text.str().find(ready_line_) != std::string::npos;
}

pid_t RobotProcess::CommandPid() {
  if (!sandboxed_) return pid_;
  // The image's command is the only child of the sandbox's init; none yet while bubblewrap is
  // still setting the sandbox up (it can take seconds when hundreds start on a busy host).
  const pid_t init = SandboxInit();
  const pid_t command = init > 0 ? FirstChild(init) : -1;
  return command > 0 ? command : pid_;
}

void RobotProcess::Terminate() {
  const pid_t command = CommandPid();
  // bubblewrap forwards no signal, so the command gets SIGTERM itself. With no command yet there
  // is nothing to shut down gracefully: the sandbox is killed, init first, because until its
  // setup is done the init does not die with bubblewrap (its parent-death signal is armed at
  // the end of the setup): killing only bubblewrap left such sandboxes running.
  if (sandboxed_ && command == pid_) {
    KillSandbox();
  } else {
    kill(command, SIGTERM);
  }
}

void RobotProcess::KillSandbox() {
  // podman run does not take its container with it when killed: the engine removes it (and
  // kills what is left in it) by name.
  if (container_) {
    RunProgramQuietly(
        {container_->engine_exe, "rm", "--force", "--ignore", "--time", "0", container_->name});
  }
  // Through the pidfd, never a reused pid; the kernel then ends every process of the PID
  // namespace.
  if (SandboxInit() > 0 && init_pidfd_ >= 0) {
    syscall(SYS_pidfd_send_signal, init_pidfd_, SIGKILL, nullptr, 0);
  }
  kill(pid_, SIGKILL);
}

void RobotProcess::RequestStop() {
  if (pid_ > 0 && !PollExit()) Terminate();
}

void RobotProcess::Stop(TimeNs grace_ns) {
  if (pid_ <= 0) return;
  if (!PollExit()) {
    Terminate();
    if (!WaitExit(grace_ns)) KillSandbox();
    int status = 0;
    if (!exit_status_ && waitpid(pid_, &status, 0) == pid_) exit_status_ = ShellStatus(status);
  }
  WaitSandboxGone(internal::kSandboxEndTimeoutNs);
}

}  // namespace sitlnet::images
