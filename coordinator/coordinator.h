// sitlnet coordinator: one clock for physics and network, stepped in
// lock-step ("decoupled time steps", DANCERS paper Sec. III-A), over
// in-process calls or length-prefixed protobuf on Unix/TCP sockets, with
// realtime or lockstep pacing and per-iteration metrics. docs/coordinator.md
// explains the time model, the messages and the guarantees.
//
// Sections: connectors and transport (coordinator/connector.h,
// coordinator/transport.h), pacing (coordinator/pacer.h), metrics
// (coordinator/metrics.h), signals (common.h's StopSignal), and below the
// run loop itself.
#ifndef SITLNET_COORDINATOR_COORDINATOR_H_
#define SITLNET_COORDINATOR_COORDINATOR_H_

#include <cstdint>
#include <functional>
#include <string>

#include "common/common.h"
#include "coordinator/authentication.h"
#include "coordinator/connector.h"
#include "coordinator/metrics.h"
#include "coordinator/pacer.h"
#include "coordinator/transport.h"
#include "scenario/scenario.h"

namespace sitlnet::coordinator {

//------------------------------ Scenario identity ----------------------------

// FNV-1a 64 of the scenario's deterministic protobuf serialization: equal for
// the same scenario however its text is formatted. Exchanged in the handshake.
uint64_t ScenarioHash(const Scenario& scenario);

//--------------------------------- The run ----------------------------------

struct CoordinatorOptions {
  TimeNs iteration_ns = 10 * kNsPerMs;  // Δ
  int64_t iterations = 0;               // Run [0, iterations·Δ).
  Pacing pacing = Pacing::kRealtime;
  double realtime_factor = 1.0;
  // Physics sends CommandsCollected before the network may start (the
  // robot-facing lockstep protocol, docs/coordinator.md).
  bool lockstep_robots = false;
  // Longest wait for any answer of a connector within one iteration.
  TimeNs answer_timeout_ns = 5 * kNsPerS;
  // Realtime: warn when an iteration ends later than this behind its deadline
  // (at most one warning per wall second).
  TimeNs lag_warning_ns = 10 * kNsPerMs;
  clock::WallClock* wall_clock = nullptr;  // nullptr: clock::DefaultWallClock().
  // Receives the run's timebase (virtual time 0's wall instant) before iteration 0 starts, for
  // a simulator that paces parts of its work on the same wall clock. May be null.
  clock::Timebase* timebase_out = nullptr;
  int interrupt_fd = -1;                    // StopSignal::fd(); -1: none.
  MetricsCsvWriter* metrics_csv = nullptr;  // May be null.
  MetricsCollector* metrics = nullptr;      // May be null.
  // Each iteration's metrics row, on the coordinator's thread; may be empty. It must not block.
  std::function<void(const IterationMetrics&)> on_iteration;
  // Receives warnings (one line each); empty: printed to stderr.
  std::function<void(const std::string&)> warn;
};

// Δ, iteration count, pacing and factor from the scenario's Timing; pacing
// may be overridden by the caller afterwards.
CoordinatorOptions OptionsFromScenario(const Scenario& scenario);

struct RunResult {
  int64_t iterations_done = 0;
  bool interrupted = false;  // interrupt_fd fired: stopped early, outputs flushed.
};

// Runs iterations 0 .. options.iterations-1. Each iteration k: START
// [kΔ, (k+1)Δ) to physics and to network (with the poses physics reported
// at kΔ), both run in parallel, both answer END; then pacing. At the end, or
// when interrupted, both connectors get Stop and the metrics are flushed.
// Throws Error naming the connector and iteration when one fails, crashes
// or times out (the other connector is stopped first, the metrics flushed).
RunResult RunCoordinator(Connector& physics, Connector& network, const CoordinatorOptions& options);

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_COORDINATOR_H_
