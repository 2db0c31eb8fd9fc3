// Children are waited for through pidfds beside the stop signal's fd in one poll(2): a run's end
// or a Ctrl-C wakes the sweep at once, with no polling interval.
#include "sweep/point_runs.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <exception>

#include "common/common.h"

namespace sitlnet::sweep {
namespace {

struct Running {
  pid_t pid = -1;
  UniqueFd pidfd;
  size_t index = 0;
  int slot = 0;
};

pid_t StartChild(const PointCommand& command) {
  std::vector<char*> args;
  for (const std::string& arg : command.argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const int log_fd = open(command.log_path.c_str(),
                          O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
  if (log_fd < 0) throw Error(SystemErrorMessage("open log \"" + command.log_path + "\"", errno));
  const pid_t pid = fork();
  if (pid < 0) {
    close(log_fd);
    throw Error(SystemErrorMessage("fork for \"" + command.log_path + "\"", errno));
  }
  if (pid == 0) {
    // A group of its own: a terminal's Ctrl-C reaches the sweep alone, which passes it on once.
    setpgid(0, 0);
    sigset_t none;
    sigemptyset(&none);
    sigprocmask(SIG_SETMASK, &none, nullptr);
    const int null_fd = open("/dev/null", O_RDONLY);
    if (null_fd >= 0) dup2(null_fd, STDIN_FILENO);
    dup2(log_fd, STDOUT_FILENO);
    dup2(log_fd, STDERR_FILENO);
    execv(args[0], args.data());
    _exit(127);
  }
  close(log_fd);
  return pid;
}

int ExitStatus(int status) {
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : 1;
}

}  // namespace

bool RunPoints(size_t count, int jobs,
               const std::function<PointCommand(size_t index, int slot)>& prepare,
               const std::function<void(const PointExit&)>& done) {
  SITLNET_DEMAND(jobs >= 1);
  StopSignal stop;
  std::vector<Running> running;
  std::vector<bool> slot_busy(jobs, false);
  size_t next = 0;
  bool stopping = false;
  std::exception_ptr failure;
  // Once: sitlnet run takes SIGINT as Ctrl-C, stops in order and removes its namespaces.
  const auto stop_all_once = [&] {
    if (stopping || !stop.requested()) return;
    stopping = true;
    for (const Running& child : running) kill(child.pid, SIGINT);
  };
  while ((next < count && !stopping) || !running.empty()) {
    stop_all_once();
    while (!stopping && next < count && static_cast<int>(running.size()) < jobs) {
      int slot = 0;
      while (slot_busy[slot]) ++slot;
      const size_t index = next++;
      Running child;
      child.index = index;
      child.slot = slot;
      try {
        child.pid = StartChild(prepare(index, slot));
      } catch (const Error&) {
        // The runs already started are stopped and waited for before the error is reported.
        if (!failure) failure = std::current_exception();
        stop.Request();
        break;
      }
      child.pidfd.Reset(static_cast<int>(syscall(SYS_pidfd_open, child.pid, 0)));
      SITLNET_DEMAND(child.pidfd.valid());
      slot_busy[slot] = true;
      running.push_back(std::move(child));
    }
    std::vector<pollfd> fds = {{stop.fd(), POLLIN, 0}};
    for (const Running& child : running) fds.push_back({child.pidfd.get(), POLLIN, 0});
    if (poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      throw Error(SystemErrorMessage("poll the sweep's runs", errno));
    }
    stop_all_once();
    for (size_t i = running.size(); i-- > 0;) {
      if (!(fds[i + 1].revents & (POLLIN | POLLHUP))) continue;
      int status = 0;
      while (waitpid(running[i].pid, &status, 0) < 0 && errno == EINTR) {
      }
      slot_busy[running[i].slot] = false;
      try {
        done({running[i].index, running[i].slot, ExitStatus(status), stopping});
      } catch (const Error&) {
        if (!failure) failure = std::current_exception();
        stop.Request();
      }
      running.erase(running.begin() + static_cast<std::ptrdiff_t>(i));
    }
  }
  if (failure) std::rethrow_exception(failure);
  return stopping;
}

}  // namespace sitlnet::sweep
