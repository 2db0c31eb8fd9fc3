// LiveView: `sitlnet run --view`, the run's LiveFeed served while the run goes.
#include <atomic>
#include <cstdio>
#include <memory>
#include <mutex>
#include <thread>

#include "view/http_server.h"
#include "view/live_feed.h"
#include "view/live_json.h"
#include "view/live_modes.h"
#include "view/replay_json.h"
#include "view/view.h"

namespace sitlnet::view {
namespace {

// /api/live is built at most this often, however many browsers ask: a bounded cost.
constexpr TimeNs kLiveDocumentPeriodNs = 200 * kNsPerMs;

// /api/live, rebuilt from the feed and medium.pcap when the last one is older than
// kLiveDocumentPeriodNs.
class LiveDocument {
 public:
  LiveDocument(const LiveFeed* feed, const std::string& run_dir, int robots)
      : feed_(*feed), modes_(run_dir, robots) {}
  std::string Get() {
    std::lock_guard lock(mutex_);
    const TimeNs now_ns = MonotonicNowNs();
    if (json_.empty() || now_ns >= built_ns_ + kLiveDocumentPeriodNs) {
      const LiveSnapshot snapshot = feed_.Snapshot();
      // A first pose means the loop began: medium.pcap is this run's.
      if (snapshot.time_ns >= 0) modes_.Update();
      json_ = LiveJson(snapshot, modes_.Latest());
      built_ns_ = now_ns;
    }
    return json_;
  }

 private:
  const LiveFeed& feed_;
  LiveModes modes_;
  std::mutex mutex_;
  std::string json_;
  TimeNs built_ns_ = 0;
};

}  // namespace

struct LiveView::State {
  LiveFeed feed;
  std::atomic<uint64_t> requests{0};  // /api/live answered.
  std::unique_ptr<LiveDocument> document;
  std::unique_ptr<HttpServer> server;
  std::thread thread;
};

LiveView::LiveView(const Scenario& scenario, const std::string& run_dir,
                   const ListenAddress& listen, const std::string& web_dir)
    : state_(std::make_unique<State>()) {
  state_->document = std::make_unique<LiveDocument>(&state_->feed, run_dir,
                                                    static_cast<int>(scenario.robots.size()));
  state_->server = std::make_unique<HttpServer>(web_dir);
  auto run = std::make_shared<const std::string>(
      RunJson(scenario, run_dir, scenario.duration_ns, /*live=*/true));
  state_->server->Json("/api/run", [run](const HttpServer::Params&) { return *run; });
  state_->server->Json("/api/live", [state = state_.get()](const HttpServer::Params&) {
    ++state->requests;
    return state->document->Get();
  });
  url_ = PageUrl(state_->server->Bind(listen));
  // The server's threads take no SIGINT or SIGTERM: those are the run's (its StopSignal).
  StopSignalsBlocked blocked;
  state_->thread = std::thread([server = state_->server.get()] { server->Run(); });
}

LiveView::~LiveView() {
  state_->server->Stop();
  state_->thread.join();
}

run_formats::LiveSink* LiveView::sink() { return &state_->feed; }

std::string LiveView::CostLine() const {
  const LiveFeed::Cost cost = state_->feed.cost();
  char line[224];
  std::snprintf(line, sizeof line,
                "live view: %llu updates (%llu skipped: the server was reading), %.3f ms on the "
                "run's threads, %llu documents served, %.3f ms CPU on the server's threads",
                static_cast<unsigned long long>(cost.updates),
                static_cast<unsigned long long>(cost.skipped),
                static_cast<double>(cost.spent_ns) / kNsPerMs,
                static_cast<unsigned long long>(state_->requests.load()),
                static_cast<double>(state_->server->CpuNs()) / kNsPerMs);
  return line;
}

}  // namespace sitlnet::view
