// flocker: sitlnet's sample onboard software. Flies one multirotor with VAT
// flocking, learning its neighbours only from their UDP beacons on wlan0.
// Its clock is RobotState.sim_time_ns, so it works in realtime and lockstep.
// Usage and flags: docs/robot-images.md, or `flocker --help`.
#include <google/protobuf/text_format.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "physics_mujoco/client/physics_client.h"
#include "robot_images/flocker/beacon_ages.h"
#include "robot_images/flocker/beacon_link.h"
#include "robot_images/flocker/controller.h"
#include "robot_images/flocker/flocker_options.h"
#include "robot_images/flocker/flocking.h"
#include "robot_images/flocker/neighbour_table.h"
#include "robot_images/flocker/obstacle_points.h"
#include "sitlnet/scenario.pb.h"

namespace sitlnet::flocker {
namespace {

volatile std::sig_atomic_t g_stop = 0;
void OnSignal(int) { g_stop = 1; }

[[noreturn]] void Die(const std::string& message) {
  std::fprintf(stderr, "flocker: %s\n", message.c_str());
  std::exit(2);
}

AirframeParams ToParams(const proto::Airframe& a) {
  AirframeParams p;
  p.mass_kg = a.mass_kg();
  p.arm_x_m = a.arm_x_m();
  p.arm_y_m = a.arm_y_m();
  p.inertia_kg_m2 = {a.ixx_kg_m2(), a.iyy_kg_m2(), a.izz_kg_m2()};
  p.thrust_coefficient = a.thrust_coefficient();
  p.drag_coefficient = a.drag_coefficient();
  p.max_rotor_speed_rad_s = a.max_rotor_speed_rad_s();
  return p;
}

VehicleState ToVehicleState(const proto::RobotState& s) {
  VehicleState v;
  v.position_m = {s.position_m().x(), s.position_m().y(), s.position_m().z()};
  v.velocity_m_s = {s.velocity_m_s().x(), s.velocity_m_s().y(), s.velocity_m_s().z()};
  v.orientation = Eigen::Quaterniond(s.orientation().w(), s.orientation().x(), s.orientation().y(),
                                     s.orientation().z());
  v.angular_velocity_rad_s = {s.angular_velocity_rad_s().x(), s.angular_velocity_rad_s().y(),
                              s.angular_velocity_rad_s().z()};
  return v;
}

double Yaw(const Eigen::Quaterniond& q) {
  return std::atan2(2 * (q.w() * q.z() + q.x() * q.y()), 1 - 2 * (q.y() * q.y() + q.z() * q.z()));
}

// The state's lidar ranges as a world-frame scan (rays are horizontal in the
// body frame; the quad flies level enough that its yaw orients them).
LidarScan ToScan(const proto::RobotState& s, double fov_deg, double yaw_rad) {
  LidarScan scan;
  const int rays = s.lidar_range_m_size();
  scan.origin_m = {s.position_m().x(), s.position_m().y()};
  for (float r : s.lidar_range_m()) scan.max_range_m = std::max(scan.max_range_m, double(r));
  // A ray reads max_range_m when it hit nothing; keep a margin for float rounding.
  scan.max_range_m *= 0.999;
  const double fov_rad = fov_deg * M_PI / 180;
  scan.first_ray_rad = yaw_rad - fov_rad / 2;
  scan.ray_step_rad = rays > 0 ? fov_rad / rays : 0;
  scan.wraps = fov_deg >= 360;
  scan.ranges_m.assign(s.lidar_range_m().begin(), s.lidar_range_m().end());
  return scan;
}

int Run(const Options& options) {
  proto::Airframe airframe;
  if (!options.airframe_text.empty() &&
      !google::protobuf::TextFormat::ParseFromString(options.airframe_text, &airframe)) {
    Die("--airframe: not a text-format Airframe");
  }
  const AirframeParams params = ToParams(airframe);
  const char* index_text = std::getenv("SITLNET_ROBOT_INDEX");
  if (index_text == nullptr) Die("SITLNET_ROBOT_INDEX is not set (run me with sitlnet exec)");
  const uint32_t me = static_cast<uint32_t>(std::atoi(index_text));

  auto client = physics_client::PhysicsClient::FromEnvironment();
  BeaconLink link(options.device, options.beacon_port, options.tos);
  NeighbourTable table(static_cast<int64_t>(options.neighbour_timeout_s * 1e9));
  BeaconAges beacon_ages;
  const FlockingParams& flocking = options.flocking;
  const ControllerGains gains;
  const int64_t beacon_period_ns =
      std::max<int64_t>(1, static_cast<int64_t>(1e9 / options.broadcast_hz));
  const int64_t log_period_ns = static_cast<int64_t>(options.log_period_s * 1e9);
  // Robots beacon out of phase, as separately booted ones would: in phase, every robot's beacon
  // reaches the medium within a millisecond of the others' in realtime pacing and they contend
  // (docs/case-study.md, "Realtime pacing"). Offsets a golden-ratio step apart stay spread for
  // any fleet size (over the period's state slots: 10 at 10 Hz beacons and 100 Hz states); they
  // are the robot's own, so lockstep runs stay reproducible.
  const double beacon_phase = std::fmod(me * 0.6180339887498949, 1.0);
  int64_t next_beacon_ns = static_cast<int64_t>(beacon_phase * beacon_period_ns);
  int64_t next_log_ns = 0;
  double yaw_rad = NAN;

  client.SendRotorSpeeds({0, 0, 0, 0}, 0);  // tells the server where to send states
  proto::RobotState state;
  int silent_ms = 0;
  while (!g_stop) {
    // Short waits so that SIGTERM is noticed within 100 ms (the client
    // retries its poll on EINTR); the announcement still repeats once a
    // second only, as before.
    if (!client.Receive(&state, 100)) {
      silent_ms += 100;
      if (silent_ms >= 1000) {
        client.SendRotorSpeeds({0, 0, 0, 0}, 0);  // server not there yet: announce again
        silent_ms = 0;
      }
      continue;
    }
    silent_ms = 0;
    const int64_t now_ns = state.sim_time_ns();
    const VehicleState vehicle = ToVehicleState(state);
    if (std::isnan(yaw_rad)) yaw_rad = Yaw(vehicle.orientation);

    for (const proto::FlockerBeacon& beacon : link.Drain()) {
      if (beacon.robot() == me) continue;
      beacon_ages.Add(beacon.sim_time_ns(), now_ns);
      table.Heard(beacon.robot(),
                  {{beacon.x_m(), beacon.y_m()}, {beacon.vx_m_s(), beacon.vy_m_s()}}, now_ns);
    }
    const std::vector<Neighbour> neighbours = table.Current(now_ns);
    const Vec2 position(vehicle.position_m.x(), vehicle.position_m.y());
    const Vec2 velocity(vehicle.velocity_m_s.x(), vehicle.velocity_m_s.y());
    // Flock only once airborne, so the swarm does not drag robots along the ground.
    const bool airborne = vehicle.position_m.z() > 0.5 * options.altitude_m;
    const Vec2 desired =
        airborne ? DesiredVelocity(flocking, position, velocity, neighbours,
                                   NearestObstaclePoints(ToScan(state, options.lidar_fov_deg,
                                                                Yaw(vehicle.orientation)),
                                                         options.obstacle_gap_m),
                                   options.target_m)
                 : Vec2::Zero();
    const RotorSpeeds speeds =
        ComputeRotorSpeeds(params, gains, vehicle, desired, options.altitude_m, yaw_rad);

    // Beacon before the command: in lockstep pacing, frames written before the
    // command for step k enter the medium during step k.
    if (now_ns >= next_beacon_ns) {
      proto::FlockerBeacon beacon;
      beacon.set_robot(me);
      beacon.set_sim_time_ns(now_ns);
      beacon.set_x_m(position.x());
      beacon.set_y_m(position.y());
      beacon.set_z_m(vehicle.position_m.z());
      beacon.set_vx_m_s(velocity.x());
      beacon.set_vy_m_s(velocity.y());
      link.Send(beacon);
      // Whole periods on, so that the robot keeps its phase also after a late first state (an
      // image that started slowly in realtime pacing).
      next_beacon_ns += ((now_ns - next_beacon_ns) / beacon_period_ns + 1) * beacon_period_ns;
    }
    client.SendRotorSpeeds(speeds, state.step());

    if (now_ns >= next_log_ns) {
      std::string heard;
      for (uint32_t index : table.Indices()) heard += " " + std::to_string(index);
      // beacon_age_ms: median/max age of the beacons read since the last line.
      std::printf("t=%.2f pos=%.2f,%.2f,%.2f vel=%.2f,%.2f neighbours=[%s ] beacon_age_ms=%s\n",
                  now_ns * 1e-9, vehicle.position_m.x(), vehicle.position_m.y(),
                  vehicle.position_m.z(), velocity.x(), velocity.y(), heard.c_str(),
                  beacon_ages.TakeSummaryMs().c_str());
      std::fflush(stdout);
      next_log_ns = now_ns + log_period_ns;
    }
  }
  return 0;
}

}  // namespace
}  // namespace sitlnet::flocker

int main(int argc, char** argv) {
  std::signal(SIGINT, sitlnet::flocker::OnSignal);
  std::signal(SIGTERM, sitlnet::flocker::OnSignal);
  const auto options = sitlnet::flocker::ParseOptions(argc, argv);
  try {
    return sitlnet::flocker::Run(options);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "flocker: %s\n", error.what());
    return 1;
  }
}
