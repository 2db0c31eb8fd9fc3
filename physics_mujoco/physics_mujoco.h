// sitlnet physics_mujoco: MuJoCo multirotors flown by robot software over each robot's ctl0
// veth. Frames, units and models are described in docs/physics.md, the wire protocols (native
// protobuf and ArduPilot JSON) in docs/protocols.md, PX4's in docs/autopilots.md.
//
// World: the pure simulation (no network): one mjData per robot on a shared mjModel per
//   airframe, rotor and motor models, IMU and lidar. PhysicsServer: a World plus every robot's
//   links, one per protocol it speaks (robot_link.h); the coordinator calls Advance(k), the
//   standalone mode RunRealtime().
#ifndef SITLNET_PHYSICS_MUJOCO_PHYSICS_MUJOCO_H_
#define SITLNET_PHYSICS_MUJOCO_PHYSICS_MUJOCO_H_

#include <array>
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "clock/clock.h"
#include "common/common.h"
#include "scenario/scenario.h"

namespace sitlnet::physics {

//--------------------------------- Values -----------------------------------

// Rotors per airframe: quad-X, in ArduPilot's motor order (1 front-right CCW, 2 rear-left CCW,
// 3 front-left CW, 4 rear-right CW).
inline constexpr int kRotors = 4;
using RotorSpeeds = std::array<double, kRotors>;  // rad/s

// Unit quaternion (w, x, y, z) rotating body-frame vectors into the world frame.
struct Quat {
  double w = 1, x = 0, y = 0, z = 0;
};

// Kinematic state of one robot. World frame ENU, body frame FLU.
struct RobotPose {
  Vec3d position_m;
  Quat orientation;
  Vec3d velocity_m_s;            // World frame.
  Vec3d angular_velocity_rad_s;  // Body frame.
};

// The scenario's local ENU frame on the WGS-84 ellipsoid (docs/autopilots.md, "Geodetic origin").
// A place on Earth: WGS-84 latitude and longitude, altitude above mean sea level.
struct GeodeticPoint {
  double latitude_deg = 0;   // North positive.
  double longitude_deg = 0;  // East positive, in [-180, 180].
  double altitude_m = 0;
};

// Maps world ENU positions (metres from the scenario's origin) to geodetic coordinates and back.
// Horizontally by the azimuthal equidistant projection on the WGS-84 ellipsoid centred at the
// origin (GeographicLib, C. F. F. Karney, "Algorithms for geodesics", J. Geodesy 87, 2013): the
// point (x, y) lies at geodesic distance hypot(x, y) from the origin, at azimuth atan2(x, y)
// from north, exact to the nanometre. Vertically, altitude = origin altitude + z: the flat
// simulated ground follows the ellipsoid (geoid height ignored). Cheap to copy.
class GeodeticFrame {
 public:
  explicit GeodeticFrame(const proto::GeodeticOrigin& origin);

  GeodeticPoint ToGeodetic(const Vec3d& enu_m) const;
  // Inverse of ToGeodetic (to the nanometre within 1000 km of the origin).
  Vec3d ToEnu(const GeodeticPoint& point) const;
  const GeodeticPoint& origin() const { return origin_; }

 private:
  GeodeticPoint origin_;
};

// One IMU sample in the body frame (FLU), noise and bias included.
struct ImuSample {
  Vec3d gyro_rad_s;
  Vec3d accel_m_s2;  // Specific force: (0, 0, +9.81) at rest.
};

//---------------------------------- World -----------------------------------

enum class Integrator {
  kEuler,  // MuJoCo's semi-implicit Euler: position lags z0 - g t^2/2 by g t dt / 2.
  kRk4,    // 4th-order Runge-Kutta: exact for constant acceleration (default).
};

struct WorldOptions {
  // Unset: the scenario's timing.physics_integrator (RK4 by default).
  std::optional<Integrator> integrator;
  int threads = 2;  // Threads stepping robots, the caller's included (>= 1).
  // Obstacle culling (docs/physics.md): each robot's model holds only the obstacles within
  // reach of its square tile of side cull_tile_m; trajectories and lidar ranges are the same
  // as with every obstacle in one model (tested bit for bit). false: one model holds all.
  bool cull_obstacles = true;
  double cull_tile_m = 20;
  // Tile models are compiled when the World is built if at most this many tiles are near an
  // obstacle, else each on first use, inside a step (docs/physics.md, "Obstacle culling").
  int64_t cull_tiles_compiled_up_front = 1024;
  // The robots this World simulates, by global index (RobotPlan::index), ascending; empty:
  // every robot of the scenario. A node host (issue 35) simulates its own robots only: each
  // robot's model, seeds and results depend on its global index alone, not on the others.
  std::vector<int> robots = {};
};

// Physics steps for one robot (World::Advance of some robots).
struct RobotSteps {
  int robot = 0;  // Global index.
  int steps = 0;  // >= 0.
};

// The MuJoCo world of a scenario. Not thread-safe: one caller at a time.
class World {
 public:
  // Builds one model per airframe and one mjData per robot at its start pose. Throws Error
  // naming the airframe if MuJoCo rejects a model, or if options.robots is not ascending
  // indices of the scenario. `scenario` must outlive the World. Every `robot` argument below
  // is a global index of a robot the World simulates.
  explicit World(const Scenario& scenario, const WorldOptions& options = {});
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // How many robots the World simulates, and their global indices, ascending.
  int robot_count() const;
  const std::vector<int>& robots() const;
  bool simulates(int robot) const;
  TimeNs step_ns() const;
  // The world's virtual time: every robot's (one clock, kept by resets). Robots advanced
  // apart (Advance of some robots) each have their own until brought level: then the first's.
  TimeNs now_ns() const;
  // Virtual time of a robot (steps taken x step_ns).
  TimeNs time_ns(int robot) const;
  int64_t steps(int robot) const;

  // Advances every robot by `steps` physics steps: one clock for the whole world.
  void Advance(int steps);
  // Advances each listed robot by its own steps; the others stand. A robot's flight does not
  // depend on how its steps are split into calls, nor on the other robots (tested bit for
  // bit). Listed robots are split over the threads; each robot at most once.
  void Advance(const std::vector<RobotSteps>& robots);

  // Target rotor speeds, reached through the first-order motor lag. Clamped to
  // [0, max_rotor_speed_rad_s].
  void SetRotorTarget(int robot, const RotorSpeeds& target_rad_s);
  // Sets target and actual speeds at once (no lag): tests and initial conditions.
  void SetRotorSpeeds(int robot, const RotorSpeeds& speeds_rad_s);
  const RotorSpeeds& rotor_speeds(int robot) const;
  const RotorSpeeds& rotor_target(int robot) const;

  RobotPose Pose(int robot) const;
  // Draws noise from the robot's seeded generator: call once per published sample.
  ImuSample Imu(int robot);
  // Ranges (m) of the robot's lidar rays (empty without lidar), see robot.proto.
  void Lidar(int robot, std::vector<float>* ranges_m) const;
  // Sets the linear velocity (world ENU): initial conditions for tests and scripted starts.
  void SetVelocity(int robot, const Vec3d& velocity_m_s);
  // Back to the start pose, motors stopped; its time goes on (the world has one clock).
  void ResetRobot(int robot);

  const proto::Airframe& airframe(int robot) const;

  // Obstacle culling figures (tests, benchmarks): obstacles in the robot's current model,
  // times robots moved to another model, models compiled so far.
  int obstacles_in_model(int robot) const;
  int64_t model_switches() const;
  int models_compiled() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

//------------------------------ Protocol server -----------------------------

// A PX4 robot's link, summed over its connections (docs/autopilots.md).
struct Px4Counters {
  uint64_t connections = 0;
  uint64_t reconnections = 0;
  uint64_t sensors_sent = 0;
  uint64_t gps_sent = 0;
  uint64_t actuator_controls = 0;
  uint64_t heartbeats_received = 0;
  uint64_t ignored = 0;        // Valid messages sitlnet does not act on.
  uint64_t dropped = 0;        // Bad CRC or length, unknown, MAVLink 1, non-finite outputs.
  uint64_t bytes_skipped = 0;  // Bytes that began no frame.
  uint64_t send_errors = 0;
};

// Per-robot counters; every dropped packet is counted in exactly one drop counter.
struct RobotCounters {
  uint64_t commands_accepted = 0;
  uint64_t states_sent = 0;
  uint64_t dropped_malformed = 0;       // Truncated, garbage, not a MotorCommand.
  uint64_t dropped_invalid = 0;         // Wrong rotor count, NaN, out-of-range values.
  uint64_t dropped_wrong_robot = 0;     // MotorCommand.robot is another robot's index.
  uint64_t dropped_foreign_source = 0;  // Not from this robot's ctl0 address.
  uint64_t failsafe_cuts = 0;           // Times the silence timeout cut the motors.
  uint64_t dropped_after_drop = 0;      // Commands of a robot dropped from the lock-step.
  uint64_t send_errors = 0;
  // ArduPilot JSON endpoint.
  uint64_t json_frames = 0;    // New frames (each answered at its end: 1/frame_rate later).
  uint64_t json_resends = 0;   // Repeated frame_count: last reply sent again.
  uint64_t json_restarts = 0;  // Smaller frame_count: robot reset.
  uint64_t json_missed_frames = 0;
  uint64_t json_dropped = 0;  // Bad magic/size, foreign source.
  // Realtime pacing: SITL fell too far behind the clock to catch up; its clock jumped to now.
  uint64_t json_clock_jumps = 0;
};

// An autopilot's simulator rate in wall time (docs/run.md, summary.json's autopilot_rate):
// what it answered, when, and the rate it asks for. PhysicsServer::autopilot_rate reads it.
struct AutopilotRate {
  // Simulator messages answered: PX4's actuator controls (one per HIL_SENSOR), ArduPilot's
  // servo frames. A restarted autopilot's count goes on.
  uint64_t answers = 0;
  TimeNs first_answer_wall_ns = -1;  // CLOCK_MONOTONIC of the first answer; -1: none yet.
  TimeNs last_answer_wall_ns = -1;   // Of the latest.
  // The rate it asks for: PX4 one HIL_SENSOR per 4 ms (250 Hz), ArduPilot its frames'
  // frame_rate, at most one frame per physics step. 0: not an autopilot, or none heard.
  double nominal_hz = 0;

  // Answers per wall second from the first answer to the last; 0 with fewer than two.
  double AchievedHz() const;
  // AchievedHz / nominal_hz: 1 at the autopilot's own rate; 0 without a nominal rate.
  double Ratio() const;
};

// `answers` over `wall_ns` of wall time, per second; 0 when wall_ns <= 0.
double AnswersPerSecond(uint64_t answers, TimeNs wall_ns);

struct ServerOptions {
  // world.robots also chooses the robots the server makes links for (empty: every robot).
  WorldOptions world;
  // Called with the work that makes every socket of the server, to run it: a caller wraps it to
  // make them in another network namespace (runs: the scenario's ctl namespace, nns::InNetns).
  // Empty: in the calling thread's namespace. The world's threads are made before, outside it.
  std::function<void(const std::function<void()>&)> make_sockets;

  // How the clock waits for autopilots (ArduPilot, PX4), fixed for the server's life; at most
  // one of the two. The frame gate (lockstep pacing; docs/protocols.md): in Advance() a robot
  // whose autopilot has joined (and is not dropped) steps on only once it answered its last
  // message, waiting up to this much wall time; the other robots do not wait for it (each robot
  // steps as its own autopilot answers). 0: the clock never waits for them.
  TimeNs frame_gate_timeout_ns = 0;
  // Realtime pacing (docs/autopilots.md, "ArduPilot in sitlnet's clock"): with a timebase (not
  // owned, on CLOCK_MONOTONIC, begun before the first Advance), Advance() sends what an
  // autopilot is due (an ArduPilot reply, PX4's sensors) no earlier than the wall instant of its
  // virtual time, sleeping until then, and while an autopilot's answer is awaited the world does not run
  // ahead of the wall clock (it waits for the answer up to the wall instant of its next step,
  // then steps once). Null, or no autopilot in the scenario: not held.
  const clock::Timebase* autopilot_wall_clock = nullptr;
  // Native robots' periodic states at their state rate during Advance(). Lock-step runs turn
  // them off so a robot gets exactly one state (SendStates) per iteration and nothing it
  // answers can race the coordinator.
  bool periodic_states = true;
};

// An autopilot that missed the frame gate's timeout, in its protocol's words: "robot 'a' did
// not answer <unanswered> of iteration N <expected> within T ms".
struct SilentAutopilot {
  int robot = 0;
  std::string unanswered;  // "its JSON reply", "its HIL_SENSOR"
  std::string expected;    // "with a servo frame", "with HIL_ACTUATOR_CONTROLS"
};

// A World plus, per robot, its links on RobotPlan::ctl_root_address: a UDP socket on
// physics_port (native protocol) and optionally one on ardupilot_json_port (ArduPilot JSON) and
// a TCP listener on px4_sim_port (PX4). Sockets use IP_FREEBIND, so the server may start before
// the scenario's ctl0 veths exist.
class PhysicsServer {
 public:
  // Throws Error naming the robot and address if a socket cannot be bound, or a robot's
  // state_rate_hz / command_timeout_ms / ardupilot_json_port / px4_sim_port is invalid.
  // `scenario` must outlive the server.
  explicit PhysicsServer(const Scenario& scenario, const ServerOptions& options = {});
  ~PhysicsServer();
  PhysicsServer(const PhysicsServer&) = delete;
  PhysicsServer& operator=(const PhysicsServer&) = delete;

  // Handles every packet waiting on every socket (non-blocking).
  void Poll();
  // Poll(), then advances the world by `steps`, sending each subscribed robot its RobotState at
  // its state rate, each ArduPilot robot the reply to its frame when the clock reaches the
  // frame's end, each connected PX4 robot its sensor messages every sensor period, and cutting
  // motors of robots silent past their timeout. With the frame gate on, a robot's clock does not
  // pass its autopilot's last reply or HIL_SENSOR before the answer arrived; robots step apart
  // within the call, as their own autopilots answer, and are level again when it returns.
  void Advance(int steps);

  // True if some robot has an ArduPilot JSON endpoint or a PX4 simulator link.
  bool has_frame_gated_robots() const;
  // Autopilots that missed the frame gate's timeout since the last call (each once until it
  // answers again), for the caller's on_silent_robot policy; those of one protocol together.
  std::vector<SilentAutopilot> TakeSilentAutopilots();
  // The robot's software has made itself known: a native command, an ArduPilot frame or a PX4
  // connection.
  bool spoke(int robot) const;
  // The PX4 link's counters of a robot with px4_sim_port.
  std::optional<Px4Counters> px4_counters(int robot) const;

  // Lock-step (docs/protocols.md, lock-step): sends every subscribed, world-clocked robot its
  // RobotState now (on top of the periodic ones).
  void SendStates();
  // Lock-step: handles packets until every subscribed, world-clocked robot has sent a command
  // whose `step` equals its current physics step count (the `step` of the state it just got),
  // or `timeout_ns` of wall time passed. Returns the robots still missing (empty: all in).
  // Robot software joins the lock-step with its first command; others are not waited for.
  std::vector<int> CollectCommands(TimeNs timeout_ns);
  // Takes a robot out of the lock-step for the rest of the run (a silent robot, by the
  // scenario's on_silent_robot policy): its motors are cut, it gets no more states, and its
  // later commands are dropped and counted (dropped_after_drop).
  void DropFromLockstep(int robot);

  // An fd that becomes readable when Poll() has packets to handle (epoll).
  int wait_fd() const;
  World& world();
  const World& world() const;
  const RobotCounters& counters(int robot) const;
  // The robot's autopilot rate (nominal_hz 0 without an autopilot). Safe from any thread while
  // the server steps: the progress line reads it from the coordinator's.
  AutopilotRate autopilot_rate(int robot) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Standalone realtime mode (`sitlnet physics`): advances the server one physics step at a
// time, virtual time following the wall clock x the scenario's realtime_factor, handling
// packets as they arrive, until `stop_fd` is readable (a StopSignal's fd; -1: none) or
// `duration_ns` of virtual time has passed (<= 0: no limit). Returns the largest lag behind the
// wall clock seen, in ns.
TimeNs RunRealtime(PhysicsServer* server, double realtime_factor, TimeNs duration_ns,
                   int stop_fd);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_PHYSICS_MUJOCO_H_
