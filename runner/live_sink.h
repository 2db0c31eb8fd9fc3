// What `sitlnet run --view` is told while the run goes (view/live_feed.h): the robots' poses at
// every trajectories.csv sample, each second's links as links.csv will count them, each
// connectivity.csv sample, each second's iteration timing, and what the GCS relay heard. Called
// on the run's own threads (physics, coordinator), at most every 100 ms of simulated time each:
// an implementation must never block or wait. One exception, bounded: the GCS relay's counts are
// copied at most every 200 ms of wall time under the relay's lock, which its thread holds for
// one wake-up's work (runner/gcs_relay_stage.cc).
#ifndef SITLNET_RUNNER_LIVE_SINK_H_
#define SITLNET_RUNNER_LIVE_SINK_H_

#include <cstdint>
#include <string>
#include <vector>

#include "common/common.h"
#include "runner/second_timing.h"

namespace sitlnet::runner {

struct LivePose {
  double x_m = 0, y_m = 0, z_m = 0;
  double speed_m_s = 0;
};

// One links.csv row: DATA frames from `from` at station `to` in a second (to -1: sender drops
// of group frames), those decoded, and the most frequent loss.
struct LinkRow {
  int64_t second = 0;
  int from = 0, to = 0;
  uint64_t frames = 0, delivered = 0;
  const char* main_cause = "none";
  uint64_t main_cause_frames = 0;
  // The PHY rate and, for HT/VHT, the MCS (else -1) of the link's last DATA frame in the second.
  double rate_mbps = 0;
  int mcs = -1;
};

// What the GCS relay heard of one vehicle (a MAVLink system id) so far: gcs::VehicleCounters,
// with the robot whose radio address sent it.
struct LiveVehicle {
  int robot = -1;  // Robot index; -1: no robot of the scenario has the sender's address.
  uint8_t system_id = 0;
  uint64_t messages = 0;
  uint64_t sequence_gaps = 0;   // Frames missing by sequence numbers: MAVLink loss over the radio.
  bool heartbeat_seen = false;  // An autopilot's HEARTBEAT; the fields below are its latest.
  uint8_t type = 0, autopilot = 0, base_mode = 0;  // MAV_TYPE, MAV_AUTOPILOT, MAV_MODE_FLAG
  uint32_t custom_mode = 0;
  bool armed = false;
};

class LiveSink {
 public:
  virtual ~LiveSink() = default;
  // Physics thread: every robot's pose (by index) at `time_ns`, as trajectories.csv samples it.
  virtual void Poses(TimeNs time_ns, const std::vector<LivePose>& poses) = 0;
  // Coordinator thread: the rows of a second no transmission can still add to.
  virtual void Links(int64_t second, const std::vector<LinkRow>& rows) = 0;
  // Coordinator thread: connectivity.csv's row at `time_ns` (every 100 ms of simulated time,
  // once a later delivery or the run's end shows it): the count of components and, per robot,
  // its component's smallest robot index.
  virtual void Components(TimeNs time_ns, int components, const std::vector<int>& component_of) = 0;
  // Coordinator thread: a simulated second's iterations (metrics.csv), once the next began.
  virtual void Timing(const SecondTiming& second) = 0;
  // Coordinator thread, a few times a second of wall time in a run with a GCS relay: every
  // vehicle the relay heard, by system id, at simulated time `time_ns`.
  virtual void Vehicles(TimeNs /*time_ns*/, const std::vector<LiveVehicle>& /*vehicles*/) {}
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_LIVE_SINK_H_
