// sitlnet view: a web page of a run (docs/view.md). `sitlnet view RUN_DIR` replays a finished
// run folder: the map from above, robots and trails, links coloured by delivery ratio, a time
// slider, and each link's frames with the cause of each loss. The CLI's only way in.
#ifndef SITLNET_VIEW_VIEW_H_
#define SITLNET_VIEW_VIEW_H_

#include <functional>
#include <string>

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

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_VIEW_H_
