#include <fcntl.h>
#include <pthread.h>
#include <poll.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>

#include "common/common.h"

namespace sitlnet {
namespace {

std::atomic<int> g_write_fd{-1};
std::atomic<int> g_signal{0};

void OnSignal(int signal_number) {
  const int saved_errno = errno;
  g_signal.store(signal_number);
  const int fd = g_write_fd.load();
  if (fd >= 0) {
    const char byte = 1;
    [[maybe_unused]] ssize_t ignored = write(fd, &byte, 1);
  }
  errno = saved_errno;
}

}  // namespace

StopSignal::StopSignal() {
  int fds[2];
  if (pipe2(fds, O_CLOEXEC | O_NONBLOCK) < 0) {
    throw Error(SystemErrorMessage("create stop-signal pipe", errno));
  }
  read_fd_ = fds[0];
  write_fd_ = fds[1];
  SITLNET_DEMAND(g_write_fd.exchange(write_fd_) == -1);  // One instance at a time.
  g_signal.store(0);
  struct sigaction action {};
  action.sa_handler = OnSignal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, &previous_int_);
  sigaction(SIGTERM, &action, &previous_term_);
}

StopSignal::~StopSignal() {
  sigaction(SIGINT, &previous_int_, nullptr);
  sigaction(SIGTERM, &previous_term_, nullptr);
  g_write_fd.store(-1);
  close(read_fd_);
  close(write_fd_);
}

bool StopSignal::requested() const {
  pollfd p{read_fd_, POLLIN, 0};
  return poll(&p, 1, 0) == 1;
}

void StopSignal::Wait() const {
  pollfd p{read_fd_, POLLIN, 0};
  while (poll(&p, 1, -1) < 0 && errno == EINTR) {
  }
}

int StopSignal::signal_number() const { return g_signal.load(); }

void StopSignal::Request() {
  const char byte = 1;
  [[maybe_unused]] ssize_t ignored = write(write_fd_, &byte, 1);
}

StopSignalsBlocked::StopSignalsBlocked() {
  sigset_t signals;
  sigemptyset(&signals);
  sigaddset(&signals, SIGINT);
  sigaddset(&signals, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &signals, &previous_);
}

StopSignalsBlocked::~StopSignalsBlocked() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }

}  // namespace sitlnet
