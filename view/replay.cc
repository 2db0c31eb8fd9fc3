// ServeReplay: the run folder, the server, and the signals that stop it.
#include <pthread.h>
#include <signal.h>

#include <atomic>
#include <thread>

#include "common/common.h"
#include "view/http_server.h"
#include "view/run_record.h"
#include "view/view.h"

namespace sitlnet::view {
namespace {

// SIGINT and SIGTERM are blocked in every thread (cpp-httplib's workers inherit the mask) and
// taken by sigwait in one thread, which stops the server: no work in a signal handler.
class StopOnSignal {
 public:
  explicit StopOnSignal(HttpServer* server) {
    sigemptyset(&signals_);
    sigaddset(&signals_, SIGINT);
    sigaddset(&signals_, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals_, &previous_);
    waiter_ = std::thread([this, server] {
      int signal = 0;
      sigwait(&signals_, &signal);
      signalled_ = true;
      server->Stop();
    });
  }
  // The server stopped: wake the waiter (if no signal did) and restore the mask.
  ~StopOnSignal() {
    if (!signalled_) pthread_kill(waiter_.native_handle(), SIGTERM);
    waiter_.join();
    pthread_sigmask(SIG_SETMASK, &previous_, nullptr);
  }

 private:
  sigset_t signals_{}, previous_{};
  std::atomic<bool> signalled_ = false;
  std::thread waiter_;
};

}  // namespace

void ServeReplay(const ReplayOptions& options,
                 const std::function<void(const std::string& url)>& on_listening) {
  const RunRecord record = LoadRunRecord(options.run_dir);
  HttpServer server(record, options.web_dir);
  const ListenAddress bound = server.Bind(options.listen);
  StopOnSignal stop(&server);
  on_listening(PageUrl(bound));
  server.Run();
}

}  // namespace sitlnet::view
