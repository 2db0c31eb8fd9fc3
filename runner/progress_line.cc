#include "runner/progress_line.h"

#include <unistd.h>

#include <cstdio>

namespace sitlnet::runner {

ProgressLine::ProgressLine(bool enabled, tapbridge::BridgeCore* bridge,
                           const std::vector<RobotSlot>* robots, TimeNs duration_ns,
                           const gcs::GcsRelay* gcs_relay, const physics::PhysicsServer* physics,
                           bool realtime)
    : enabled_(enabled),
      bridge_(*bridge),
      robots_(*robots),
      duration_ns_(duration_ns),
      gcs_relay_(gcs_relay),
      physics_(physics),
      realtime_(realtime),
      answers_before_(robots->size(), 0) {}

void ProgressLine::IterationBegins(const proto::coord::Start&) {
  if (wall_start_ns_ == 0) wall_start_ns_ = last_print_wall_ns_ = MonotonicNowNs();
}

std::string ProgressLine::AutopilotRates(TimeNs wall_now_ns) {
  // Under a second since the last rates (the first line, at the first iteration): too few
  // answers for new ones; the last ones are shown again.
  if (physics_ == nullptr || wall_now_ns - last_print_wall_ns_ < kNsPerS) return rates_text_;
  int autopilots = 0;
  double lowest = 0, highest = 0;
  for (size_t i = 0; i < robots_.size(); ++i) {
    if (!physics_->world().simulates(static_cast<int>(i))) continue;
    const physics::AutopilotRate rate = physics_->autopilot_rate(static_cast<int>(i));
    if (rate.nominal_hz <= 0) continue;
    const double ratio = physics::AnswersPerSecond(rate.answers - answers_before_[i],
                                                   wall_now_ns - last_print_wall_ns_) /
                         rate.nominal_hz;
    answers_before_[i] = rate.answers;
    lowest = autopilots == 0 ? ratio : std::min(lowest, ratio);
    highest = autopilots == 0 ? ratio : std::max(highest, ratio);
    ++autopilots;
  }
  last_print_wall_ns_ = wall_now_ns;
  if (autopilots == 0) return rates_text_ = "";
  char text[96];
  std::snprintf(text, sizeof text, "autopilots %d at %.0f-%.0f %% of their rate   ", autopilots,
                100 * lowest, 100 * highest);
  return rates_text_ = text;
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
  // On a terminal the line is redrawn in place, cleared first: a shorter line leaves no tail.
  std::fprintf(stderr, isatty(STDERR_FILENO) ? "\r\033[K" : "");
  std::fprintf(stderr,
               "t=%7.2f/%.0f s  x%.2f real time  robots %d/%d  frames sent %llu delivered "
               "%llu lost %llu   ",
               sim_s, static_cast<double>(duration_ns_) / kNsPerS,
               wall_s > 0 ? sim_s / wall_s : 0.0, alive, with_image,
               static_cast<unsigned long long>(sent), static_cast<unsigned long long>(delivered),
               static_cast<unsigned long long>(lost));
  if (realtime_) {
    std::fprintf(stderr, "lag max %.1f ms   ", static_cast<double>(lag_max_ns_) / kNsPerMs);
    lag_max_ns_ = 0;
  }
  std::fputs(AutopilotRates(MonotonicNowNs()).c_str(), stderr);
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
