// Helper programs run to their end (a container engine's `rm`, gnuplot), without a shell.
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <string>
#include <vector>

#include "common/common.h"

namespace sitlnet {

int RunProgramQuietly(const std::vector<std::string>& argv) {
  if (argv.empty()) return -1;
  std::vector<char*> args;
  for (const std::string& arg : argv) args.push_back(const_cast<char*>(arg.c_str()));
  args.push_back(nullptr);
  const pid_t pid = fork();
  if (pid < 0) return -1;
  if (pid == 0) {
    // The caller may hold SCHED_FIFO (a realtime-paced run); a helper has no such need.
    ResetToNormalScheduling();
    const int null_fd = open("/dev/null", O_RDWR);
    if (null_fd >= 0) {
      for (int fd : {STDIN_FILENO, STDOUT_FILENO, STDERR_FILENO}) dup2(null_fd, fd);
    }
    execvp(args[0], args.data());
    _exit(127);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return -1;
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status) == 127 ? -1 : WEXITSTATUS(status);
  return WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
}

std::string RunGnuplot(const std::string& script, const std::string& dir,
                       const std::string& log_path) {
  int to_gnuplot[2];
  if (pipe2(to_gnuplot, O_CLOEXEC) != 0) return SystemErrorMessage("pipe to gnuplot", errno);
  const pid_t pid = fork();
  if (pid < 0) {
    const int err = errno;
    close(to_gnuplot[0]);
    close(to_gnuplot[1]);
    return SystemErrorMessage("fork gnuplot", err);
  }
  if (pid == 0) {
    ResetToNormalScheduling();
    const int null_fd = open("/dev/null", O_RDWR);
    const int log_fd =
        open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    dup2(to_gnuplot[0], STDIN_FILENO);
    dup2(log_fd >= 0 ? log_fd : null_fd, STDOUT_FILENO);
    dup2(log_fd >= 0 ? log_fd : null_fd, STDERR_FILENO);
    if (chdir(dir.c_str()) != 0) _exit(126);
    execlp("gnuplot", "gnuplot", "-", nullptr);
    _exit(127);
  }
  close(to_gnuplot[0]);
  // A gnuplot that ends early must not end us with SIGPIPE: the signal is blocked in this thread
  // while it writes, and one it raised is taken back before the mask is restored.
  sigset_t pipe_signal, previous;
  sigemptyset(&pipe_signal);
  sigaddset(&pipe_signal, SIGPIPE);
  pthread_sigmask(SIG_BLOCK, &pipe_signal, &previous);
  bool raised_pipe = false;
  for (size_t done = 0; done < script.size();) {
    const ssize_t n = write(to_gnuplot[1], script.data() + done, script.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno == EPIPE) raised_pipe = true;
    if (n <= 0) break;  // gnuplot is gone: its status says why.
    done += static_cast<size_t>(n);
  }
  close(to_gnuplot[1]);
  if (raised_pipe && !sigismember(&previous, SIGPIPE)) {
    const timespec no_wait{};
    sigtimedwait(&pipe_signal, nullptr, &no_wait);
  }
  pthread_sigmask(SIG_SETMASK, &previous, nullptr);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) return SystemErrorMessage("wait for gnuplot", errno);
  }
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) return "";
  if (WIFEXITED(status) && WEXITSTATUS(status) == 127) {
    return "gnuplot not found (apt-get install gnuplot-nox; scripts/setup does)";
  }
  return "gnuplot failed on the plots of " + dir + " (see " + log_path + ")";
}

std::string GnuplotQuoted(const std::string& text) {
  // gnuplot reads '' inside a single-quoted string as one quote, and nothing else specially.
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\n' || c == '\r') throw Error("a line break cannot go into a gnuplot label");
    quoted += c == '\'' ? std::string("''") : std::string(1, c);
  }
  return quoted + "'";
}

}  // namespace sitlnet
