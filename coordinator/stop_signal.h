// SIGINT/SIGTERM -> an orderly stop. The handler only writes a byte to a
// pipe (async-signal-safe); every blocking wait in the coordinator polls the
// read end, so a signal ends a wait at once instead of after a timeout.
#ifndef SITLNET_COORDINATOR_STOP_SIGNAL_H_
#define SITLNET_COORDINATOR_STOP_SIGNAL_H_

#include <csignal>

namespace sitlnet::coordinator {

class StopSignal {
 public:
  // Installs handlers for SIGINT and SIGTERM; one instance at a time.
  StopSignal();
  // Restores the previous handlers.
  ~StopSignal();
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;

  // Readable once a signal arrived (or Request() was called).
  int fd() const { return read_fd_; }
  bool requested() const;
  // The signal that arrived (0 if Request() or none).
  int signal_number() const;
  // Same effect as a signal (tests, a CLI "stop" command).
  void Request();

 private:
  int read_fd_ = -1;
  int write_fd_ = -1;
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_STOP_SIGNAL_H_
