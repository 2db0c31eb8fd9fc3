#include "runner/progress_line.h"

#include <unistd.h>

#include <cstdio>

namespace sitlnet::runner {

ProgressLine::ProgressLine(bool enabled, tapbridge::BridgeCore* bridge,
                           const std::vector<RobotSlot>* robots, TimeNs duration_ns,
                           const gcs::GcsRelay* gcs_relay)
    : enabled_(enabled),
      bridge_(*bridge),
      robots_(*robots),
      duration_ns_(duration_ns),
      gcs_relay_(gcs_relay) {}

void ProgressLine::IterationBegins(const proto::coord::Start&) {
  if (wall_start_ns_ == 0) wall_start_ns_ = MonotonicNowNs();
}

void ProgressLine::IterationEnded(const proto::coord::Start& start) {
  if (enabled_ && MonotonicNowNs() >= next_print_wall_ns_) {
    Print(start.end_ns());
    next_print_wall_ns_ = MonotonicNowNs() + (isatty(STDERR_FILENO) ? kNsPerS / 2 : 5 * kNsPerS);
  }
}

void ProgressLine::Print(TimeNs now_ns) {
  uint64_t sent = 0, delivered = 0, lost = 0;
  for (int i = 0; i < bridge_.robot_count(); ++i) {
    const tapbridge::MediumCounters counters = bridge_.medium_counters(i);
    sent += counters.sent;
    delivered += counters.delivered;
    lost += counters.queue_drops;
    for (const auto& [reason, count] : counters.lost) lost += count;
  }
  int alive = 0, with_image = 0;
  for (const RobotSlot& robot : robots_) {
    if (!robot.process) continue;
    ++with_image;
    if (!robot.exit_status) ++alive;
  }
  const double wall_s = static_cast<double>(MonotonicNowNs() - wall_start_ns_) / kNsPerS;
  const double sim_s = static_cast<double>(now_ns) / kNsPerS;
  std::fprintf(stderr, isatty(STDERR_FILENO) ? "\r" : "");
  std::fprintf(stderr,
               "t=%7.2f/%.0f s  x%.2f real time  robots %d/%d  frames sent %llu delivered "
               "%llu lost %llu   ",
               sim_s, static_cast<double>(duration_ns_) / kNsPerS,
               wall_s > 0 ? sim_s / wall_s : 0.0, alive, with_image,
               static_cast<unsigned long long>(sent), static_cast<unsigned long long>(delivered),
               static_cast<unsigned long long>(lost));
  if (gcs_relay_ != nullptr) {
    const gcs::GcsRelayCounters relayed = gcs_relay_->counters();
    int armed = 0;
    for (const gcs::VehicleCounters& vehicle : relayed.vehicles) armed += vehicle.armed;
    std::fprintf(stderr, "GCS: %zu vehicles, %d armed, %llu unreceived   ", relayed.vehicles.size(),
                 armed, static_cast<unsigned long long>(relayed.to_gcs_unreceived));
  }
  if (!isatty(STDERR_FILENO)) std::fputc('\n', stderr);
  printed_ = isatty(STDERR_FILENO);
}

void ProgressLine::Finish() {
  if (printed_) std::fputc('\n', stderr);
  printed_ = false;
}

}  // namespace sitlnet::runner
