#include "coordinator/coordinator.h"

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <poll.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace sitlnet::coordinator {

uint64_t ScenarioHash(const Scenario& scenario) {
  std::string bytes;
  {
    google::protobuf::io::StringOutputStream stream(&bytes);
    google::protobuf::io::CodedOutputStream coded(&stream);
    coded.SetSerializationDeterministic(true);
    scenario.spec.SerializeToCodedStream(&coded);
  }
  uint64_t hash = 14695981039346656037ull;  // FNV-1a 64 offset basis.
  for (unsigned char byte : bytes) {
    hash ^= byte;
    hash *= 1099511628211ull;  // FNV-1a 64 prime.
  }
  return hash;
}

CoordinatorOptions OptionsFromScenario(const Scenario& scenario) {
  CoordinatorOptions options;
  options.iteration_ns = scenario.iteration_ns;
  options.iterations = scenario.duration_ns / scenario.iteration_ns;
  options.pacing = scenario.pacing();
  options.realtime_factor = scenario.spec.timing().realtime_factor();
  return options;
}

namespace {

void Warn(const CoordinatorOptions& options, const std::string& line) {
  if (options.warn) {
    options.warn(line);
  } else {
    std::fprintf(stderr, "sitlnet: warning: %s\n", line.c_str());
  }
}

std::string LagWarning(const IterationMetrics& m, TimeNs iteration_ns,
                       const clock::Timebase& timebase) {
  char text[320];
  std::snprintf(
      text, sizeof text,
      "coordinator behind real time by %.1f ms at iteration %lld (virtual %.3f s): "
      "iteration took %.2f ms (physics %.2f, network %.2f, overhead %.2f) for a "
      "budget of %.2f ms (Δ %.2f ms / factor %g)",
      static_cast<double>(m.lag_ns) / kNsPerMs, static_cast<long long>(m.iteration),
      static_cast<double>(m.start_ns) / kNsPerS, static_cast<double>(m.t_total_ns) / kNsPerMs,
      static_cast<double>(m.t_phy_ns) / kNsPerMs, static_cast<double>(m.t_net_ns) / kNsPerMs,
      static_cast<double>(m.t_overhead_ns) / kNsPerMs,
      static_cast<double>(timebase.WallSpanOf(iteration_ns)) / kNsPerMs,
      static_cast<double>(iteration_ns) / kNsPerMs, timebase.realtime_factor());
  return text;
}

// Stops both connectors and flushes metrics whichever way the run ends.
class RunGuard {
 public:
  RunGuard(Connector& physics, Connector& network, const CoordinatorOptions& options)
      : physics_(physics), network_(network), options_(options) {}
  ~RunGuard() {
    physics_.Stop(reason_);
    network_.Stop(reason_);
    if (options_.metrics_csv) {
      try {
        options_.metrics_csv->Flush();
      } catch (const Error& e) {
        std::fprintf(stderr, "sitlnet: %s\n", e.what());
      }
    }
  }
  void set_reason(std::string reason) { reason_ = std::move(reason); }

 private:
  Connector& physics_;
  Connector& network_;
  const CoordinatorOptions& options_;
  std::string reason_ = "coordinator failed";
};

}  // namespace

RunResult RunCoordinator(Connector& physics, Connector& network,
                         const CoordinatorOptions& options) {
  SITLNET_DEMAND(physics.role() == Role::kPhysics && network.role() == Role::kNetwork);
  SITLNET_DEMAND(options.iteration_ns > 0 && options.iterations >= 0);
  clock::WallClock& wall_clock =
      options.wall_clock ? *options.wall_clock : clock::DefaultWallClock();
  Pacer pacer(options.pacing, options.realtime_factor, options.iteration_ns);
  LagWarner lag_warner(options.lag_warning_ns, kNsPerS);
  RunGuard guard(physics, network, options);
  RunResult result;

  proto::coord::Start phy_start;
  proto::coord::Start net_start;
  *net_start.mutable_poses() = physics.initial_poses();
  proto::coord::End phy_end;
  proto::coord::End net_end;

  pacer.Begin(wall_clock.NowNs());
  if (options.timebase_out != nullptr) *options.timebase_out = pacer.timebase();
  for (int64_t k = 0; k < options.iterations; ++k) {
    const uint64_t iteration = static_cast<uint64_t>(k);
    for (proto::coord::Start* start : {&phy_start, &net_start}) {
      start->set_iteration(iteration);
      start->set_start_ns(k * options.iteration_ns);
      start->set_end_ns((k + 1) * options.iteration_ns);
    }
    const TimeNs t0 = wall_clock.NowNs();
    WaitLimits limits;
    limits.timeout_ns = options.answer_timeout_ns;
    limits.deadline_ns = MonotonicNowNs() + options.answer_timeout_ns;
    limits.interrupt_fd = options.interrupt_fd;

    bool answered = true;
    physics.Begin(phy_start, limits);
    if (options.lockstep_robots) answered = physics.AwaitCommandsCollected(iteration, limits);
    if (answered) {
      network.Begin(net_start, limits);
      // A connector working on this thread goes first, or the other's
      // iteration would not overlap with it.
      if (network.runs_on_caller_thread() && !physics.runs_on_caller_thread()) {
        answered = network.Finish(iteration, &net_end, limits) &&
                   physics.Finish(iteration, &phy_end, limits);
      } else {
        answered = physics.Finish(iteration, &phy_end, limits) &&
                   network.Finish(iteration, &net_end, limits);
      }
    }
    if (!answered) {
      result.interrupted = true;
      guard.set_reason("interrupted during iteration " + std::to_string(k));
      return result;
    }
    const TimeNs t1 = wall_clock.NowNs();
    // Physics' poses at (k+1)Δ go to the network with START k+1.
    net_start.mutable_poses()->Swap(phy_end.mutable_poses());

    IterationMetrics m;
    m.iteration = k;
    m.start_ns = k * options.iteration_ns;
    m.t_phy_ns = phy_end.busy_ns();
    m.t_net_ns = net_end.busy_ns();
    m.t_total_ns = t1 - t0;
    CompleteMetrics(options.iteration_ns, &m);
    const Pacer::Decision decision = pacer.AfterIteration(k, t1);
    m.lag_ns = decision.lag_ns;
    if (options.metrics_csv) options.metrics_csv->Append(m);
    if (options.metrics) options.metrics->Add(m);
    if (options.on_iteration) options.on_iteration(m);
    if (lag_warner.ShouldWarn(m.lag_ns, t1)) {
      Warn(options, LagWarning(m, options.iteration_ns, pacer.timebase()));
    }
    result.iterations_done = k + 1;
    bool slept = true;
    if (decision.sleep_until_ns > t1) {
      slept = wall_clock.SleepUntilOrInterruptedNs(decision.sleep_until_ns, options.interrupt_fd);
    }
    // A signal during the sleep or the last iteration ends the run here.
    if (options.interrupt_fd >= 0 && k + 1 < options.iterations) {
      pollfd p{options.interrupt_fd, POLLIN, 0};
      if (!slept || poll(&p, 1, 0) == 1) {
        result.interrupted = true;
        guard.set_reason("interrupted after iteration " + std::to_string(k));
        return result;
      }
    }
  }
  guard.set_reason("run complete");
  return result;
}

}  // namespace sitlnet::coordinator
