// ServeReplay: the run folder's documents, the server, and the signals that stop it.
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <thread>

#include "common/common.h"
#include "view/http_server.h"
#include "view/replay_json.h"
#include "view/replayed_run.h"
#include "view/sweep_folder.h"
#include "view/view.h"

namespace sitlnet::view {
namespace {

// Runs `server` until SIGINT or SIGTERM, taken by StopSignal as `sitlnet run` takes
// them (its handler only writes to a pipe). One thread waits on that pipe and stops the server.
// The server's threads block both signals, so the handler runs in the waiting thread.
void ServeUntilStopSignal(HttpServer* server) {
  StopSignal stop;
  std::thread waiter([&stop, server] {
    stop.Wait();
    server->Stop();
  });
  {
    StopSignalsBlocked blocked;
    server->Run();
  }
  stop.Request();  // Wakes the waiter if no signal did.
  waiter.join();
}

// A query parameter as a number; `fallback` when absent (none: required). Throws Error naming it.
double NumberParam(const HttpServer::Params& params, const char* name,
                   std::optional<double> fallback = std::nullopt) {
  const auto it = params.find(name);
  if (it == params.end()) {
    if (fallback) return *fallback;
    throw Error(std::string("missing parameter ") + name);
  }
  char* end = nullptr;
  const double value = std::strtod(it->second.c_str(), &end);
  if (it->second.empty() || *end != '\0' || !std::isfinite(value)) {
    throw Error(std::string("parameter ") + name + " \"" + it->second + "\" is not a number");
  }
  return value;
}

// The documents of a run folder (docs/view-reference.md, "Endpoints"); `record` outlives the
// server. Those that do not depend on a query are built once.
void AddReplayDocuments(const ReplayedRun& record, HttpServer* server) {
  const auto constant = [](std::string json) {
    return [json = std::make_shared<const std::string>(std::move(json))](
               const HttpServer::Params&) { return *json; };
  };
  server->Json("/api/run", constant(RunJson(record)));
  server->Json("/api/trajectories", constant(TrajectoriesJson(record)));
  server->Json("/api/links", constant(LinksJson(record)));
  server->Json("/api/timeline", constant(TimelineJson(record)));
  server->Json("/api/modes", constant(ModesJson(record)));
  server->Json("/api/summary", constant(record.summary_json));
  server->Json("/api/gcs", constant(GcsJson(record)));
  server->Json("/api/frames", [&record](const HttpServer::Params& params) {
    const double from = NumberParam(params, "from");
    const double station = NumberParam(params, "to");
    const double end_s = NumberParam(params, "t");
    const double window_s = NumberParam(params, "window", 1.0);
    return FramesJson(record, static_cast<int>(from), static_cast<int>(station),
                      static_cast<TimeNs>(std::llround(end_s * kNsPerS)),
                      static_cast<TimeNs>(std::llround(window_s * kNsPerS)));
  });
}

}  // namespace

void ServeReplay(const ReplayOptions& options,
                 const std::function<void(const std::string& url)>& on_listening) {
  if (IsSweepFolder(options.run_dir)) {
    const auto sweep = std::make_shared<const std::string>(SweepJson(options.run_dir));
    HttpServer server(options.web_dir);
    server.Json("/api/sweep", [sweep](const HttpServer::Params&) { return *sweep; });
    on_listening(PageUrl(server.Bind(options.listen)) + kSweepPage);
    ServeUntilStopSignal(&server);
    return;
  }
  const ReplayedRun record = LoadReplayedRun(options.run_dir);
  HttpServer server(options.web_dir);
  AddReplayDocuments(record, &server);
  const ListenAddress bound = server.Bind(options.listen);
  on_listening(PageUrl(bound));
  ServeUntilStopSignal(&server);
}

}  // namespace sitlnet::view
