// SIGINT and SIGTERM blocked in the calling thread for a scope, so that threads started there
// (the server's) never take them: they are for the thread that waits on a StopSignal.
#ifndef SITLNET_VIEW_STOP_SIGNALS_BLOCKED_H_
#define SITLNET_VIEW_STOP_SIGNALS_BLOCKED_H_

#include <pthread.h>
#include <signal.h>

namespace sitlnet::view {

class StopSignalsBlocked {
 public:
  StopSignalsBlocked() {
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, &previous_);
  }
  ~StopSignalsBlocked() { pthread_sigmask(SIG_SETMASK, &previous_, nullptr); }
  StopSignalsBlocked(const StopSignalsBlocked&) = delete;
  StopSignalsBlocked& operator=(const StopSignalsBlocked&) = delete;

 private:
  sigset_t previous_{};
};

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_STOP_SIGNALS_BLOCKED_H_
