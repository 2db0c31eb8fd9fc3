// sitlnet view: a web page of a run (docs/view.md). `sitlnet view RUN_DIR` replays a finished
// run folder: the map from above, robots and trails, links coloured by delivery ratio, a time
// slider, and each link's frames with the cause of each loss. `sitlnet run --view` shows the
// same map while the run goes. The CLI's only way in.
#ifndef SITLNET_VIEW_VIEW_H_
#define SITLNET_VIEW_VIEW_H_

#include <functional>
#include <memory>
#include <string>

#include "run_formats/run_formats.h"
#include "scenario/scenario.h"
#include "view/listen_address.h"

namespace sitlnet::view {

struct ReplayOptions {
  std::string run_dir;
  ListenAddress listen;  // ParseListenAddress: loopback unless allowed.
  std::string web_dir;   // The built page (build/view/web).
};

// Loads the run folder, binds, calls `on_listening` with the page's URL, and serves until
// SIGINT or SIGTERM. Throws, before it serves anything, Error (one line) for an incomplete run
// folder or an unbuilt page, ListenError for an address it cannot bind.
void ServeReplay(const ReplayOptions& options,
                 const std::function<void(const std::string& url)>& on_listening);

// The live view of a run: binds at construction (throws ListenError, or Error for an unbuilt
// page), then serves on a thread of its own until destroyed. Give sink() to the run
// (runner::RunOptions::live); the run's threads never wait for the server or a browser.
class LiveView {
 public:
  LiveView(const Scenario& scenario, const std::string& run_dir, const ListenAddress& listen,
           const std::string& web_dir);
  ~LiveView();
  LiveView(const LiveView&) = delete;
  LiveView& operator=(const LiveView&) = delete;

  const std::string& url() const { return url_; }
  run_formats::LiveSink* sink();
  // "live view: N updates (S skipped: the server was reading), X ms on the run's threads, R
  // requests answered": what the view cost the run.
  std::string CostLine() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
  std::string url_;
};

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_VIEW_H_
