#include <algorithm>
#include <functional>

#include "mac_phy_sim/scenario_adapter.h"
#include "network_side/network_side.h"

namespace sitlnet::network_side {

PeriodicBroadcast::PeriodicBroadcast(int robots, TimeNs period_ns, int payload_bytes)
    : robots_(robots), period_ns_(period_ns), payload_bytes_(payload_bytes) {
  SITLNET_DEMAND(period_ns > 0 && payload_bytes >= 16);
}

void PeriodicBroadcast::FramesIn(TimeNs from_ns, TimeNs to_ns, std::vector<TimedFrame>* out) {
  // Collect per robot, then merge by instant (robot index breaks ties), so
  // the submission order is a function of time only.
  const size_t first = out->size();
  for (int i = 0; i < robots_; ++i) {
    const TimeNs offset = period_ns_ * i / robots_;
    // First n with offset + n·period >= from_ns.
    int64_t n = from_ns <= offset ? 0 : (from_ns - offset + period_ns_ - 1) / period_ns_;
    for (TimeNs at = offset + n * period_ns_; at < to_ns; at += period_ns_, ++n) {
      TimedFrame frame;
      frame.at_ns = at;
      frame.station = i;
      std::vector<uint8_t>& f = frame.ethernet_frame;
      f.assign(14 + payload_bytes_, 0);
      for (int b = 0; b < 6; ++b) f[b] = 0xff;  // Broadcast destination.
      const MacAddress mac = RobotMac(i);
      for (int b = 0; b < 6; ++b) f[6 + b] = mac.bytes[b];
      f[12] = 0x88;  // Local experimental ethertype 0x88b5 (IEEE 802).
      f[13] = 0xb5;
      for (int b = 0; b < 8; ++b) f[14 + b] = static_cast<uint8_t>(uint64_t(n) >> (8 * b));
      f[22] = static_cast<uint8_t>(i);
      out->push_back(std::move(frame));
    }
  }
  std::stable_sort(out->begin() + static_cast<std::ptrdiff_t>(first), out->end(),
                   [](const TimedFrame& a, const TimedFrame& b) {
                     return a.at_ns != b.at_ns ? a.at_ns < b.at_ns : a.station < b.station;
                   });
}

MediumSimulator::MediumSimulator(const Scenario& scenario, FrameSource* source)
    : medium_(mac::MakeMediumFromScenario(scenario)),
      source_(source),
      step_ns_(scenario.network_step_ns) {}

namespace {

void ApplyPoses(const proto::coord::Poses& poses, TimeNs at_ns, mac::Medium* medium) {
  const int n = std::min(medium->station_count(), poses.position_m_size() / 3);
  for (int i = 0; i < n; ++i) {
    medium->SetStationPosition(
        i, Vec3d{poses.position_m(3 * i), poses.position_m(3 * i + 1), poses.position_m(3 * i + 2)},
        at_ns);
  }
}

// One δ_net step: frames of [t, t+δ) in, medium to t+δ. Shared by the
// connector and the stand-alone reference so both do exactly the same calls.
void StepMedium(mac::Medium* medium, FrameSource* source, TimeNs t, TimeNs step_ns,
                std::vector<TimedFrame>* frames, std::vector<mac::Delivery>* deliveries) {
  frames->clear();
  if (source) source->FramesIn(t, t + step_ns, frames);
  for (const TimedFrame& f : *frames) medium->SubmitFrame(f.station, f.ethernet_frame, f.at_ns);
  // Deliveries due exactly at t+δ belong to this step (AdvanceTo runs <= until).
  medium->AdvanceTo(t + step_ns, deliveries);
}

void Record(const std::vector<mac::Delivery>& in, std::vector<mac::Delivery>* out) {
  out->insert(out->end(), in.begin(), in.end());
}

}  // namespace

void MediumSimulator::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                   IterationContext& context) {
  ApplyPoses(start.poses(), start.start_ns(), &medium_);
  for (TimeNs t = start.start_ns(); t < start.end_ns(); t += step_ns_) {
    deliveries_.clear();
    StepMedium(&medium_, source_, t, step_ns_, &frames_, &deliveries_);
    delivery_count_ += deliveries_.size();
    if (record_) Record(deliveries_, &records_);
  }
}

}  // namespace sitlnet::network_side
