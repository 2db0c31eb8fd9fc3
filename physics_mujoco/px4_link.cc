// PX4's simulator MAVLink interface on the robot's px4_sim_port (docs/autopilots.md): the
// robot's Px4Robot (connection, sensor models, messages) in the server's clock. PX4 answers each
// HIL_SENSOR with HIL_ACTUATOR_CONTROLS once it runs its lock-step.
#include <functional>
#include <limits>
#include <memory>
#include <optional>

#include "physics_mujoco/px4_robot.h"
#include "physics_mujoco/robot_link.h"

namespace sitlnet::physics {
namespace {

class Px4Link final : public RobotLink {
 public:
  Px4Link(const RobotLinkSetup& setup, uint16_t port)
      : robot_(*setup.robot),
        world_(*setup.robot->world),
        frame_(setup.scenario->spec.geodetic_origin()),
        px4_(*setup.scenario, setup.plan->index, port, &frame_),
        watch_(setup.watch) {
    watch_(this, px4_.link().listen_fd());
  }

  // Takes what PX4 sent: a new connection (PX4 restarted: the robot is back at its start and
  // rejoins the lock-step), its latest motor outputs (ignored while the robot is dropped).
  void Poll() override { Take(px4_.PollLink(&world_)); }

  // Only the readable fd: accept4 when the listener is (a new PX4), recv when the connection is.
  void PollReadable(int fd) override {
    if (fd == px4_.link().listen_fd()) {
      Take(px4_.AcceptLink(&world_));
    } else {
      px4_.ReadLink();
      Take(false);
    }
  }

  int StepsUntilDue() const override {
    if (!px4_.link().connected()) return std::numeric_limits<int>::max();
    return StepsUntil(px4_.next_sensor_ns(), world_.time_ns(robot_.robot), world_.step_ns());
  }

  // Sends the sensor messages when due (at the world's current time). What PX4 sent is taken
  // when its fd is readable (PollReadable), not here: a step costs one send.
  void Serve() override { px4_.SendDue(&world_, world_.time_ns(robot_.robot)); }

  bool spoke() const override { return px4_.link().counters().connections > 0; }

  bool paced() const override { return true; }
  bool DueNow() const override {
    return px4_.link().connected() && world_.time_ns(robot_.robot) >= px4_.next_sensor_ns();
  }
  // PX4's controls for its last HIL_SENSOR (in lock-step: Px4SimulatorLink::awaiting_answer).
  bool AnswerOutstanding() const override {
    return !robot_.dropped && px4_.link().awaiting_answer();
  }
  UnansweredMessage unanswered() const override {
    return {"its HIL_SENSOR", "with HIL_ACTUATOR_CONTROLS"};
  }

  void ReportPx4(std::optional<Px4Counters>* counters) const override {
    const Px4LinkCounters& link = px4_.link().counters();
    const mavlink::ParserCounters& parser = link.parser;
    Px4Counters& out = counters->emplace();
    out.connections = link.connections;
    out.reconnections = link.reconnections;
    out.sensors_sent = link.sensors_sent;
    out.gps_sent = link.gps_sent;
    out.actuator_controls = link.actuator_controls;
    out.heartbeats_received = link.heartbeats_received;
    out.ignored = link.ignored;
    out.dropped = link.dropped_invalid + parser.bad_crc + parser.bad_length +
                  parser.unknown_messages + parser.mavlink1_frames;
    out.bytes_skipped = parser.bytes_skipped;
    out.send_errors = link.send_errors;
  }

 private:
  // After PX4's messages were taken: a reconnected PX4 rejoins the lock-step (the robot is back
  // at its start); a new connection joins the epoll set; the latest motor outputs apply (not
  // while the robot is dropped).
  void Take(bool reconnected) {
    if (reconnected) {
      robot_.Rejoin();
      Unmute();
    }
    const Px4SimulatorLink& link = px4_.link();
    if (link.connection_fd() >= 0 && link.counters().connections != watched_connection_) {
      watched_connection_ = link.counters().connections;
      watch_(this, link.connection_fd());
    }
    if (link.answered_last_sensor()) Unmute();  // Answering again.
    const uint64_t controls = link.counters().actuator_controls;
    if (controls > metered_controls_) {
      robot_.answers.Answered(controls - metered_controls_,
                              static_cast<double>(kNsPerS) / px4_.sensor_period_ns(),
                              MonotonicNowNs());
      metered_controls_ = controls;
    }
    if (!robot_.dropped) world_.SetRotorTarget(robot_.robot, link.command().rotor_speeds_rad_s);
  }

  RobotLinkContext& robot_;
  World& world_;
  GeodeticFrame frame_;  // For the GPS.
  Px4Robot px4_;
  std::function<void(RobotLink* link, int fd)> watch_;
  // The connection in the epoll set, by its number among the link's connections: a new
  // connection can reuse the closed one's fd number (and a closed fd leaves the set by itself).
  uint64_t watched_connection_ = 0;
  uint64_t metered_controls_ = 0;  // Actuator controls counted in robot_.answers so far.
};

}  // namespace

std::unique_ptr<RobotLink> MakePx4Link(const RobotLinkSetup& setup) {
  const proto::Robot& spec = setup.plan->spec;
  if (spec.px4_sim_port() == 0) return nullptr;
  if (spec.px4_sim_port() > 65535 ||
      spec.px4_sim_port() == setup.scenario->spec.addresses().physics_port() ||
      spec.px4_sim_port() == spec.ardupilot_json_port()) {
    throw Error(setup.who + ": px4_sim_port must be in [1, 65535] and differ from physics_port");
  }
  return std::make_unique<Px4Link>(setup, static_cast<uint16_t>(spec.px4_sim_port()));
}

}  // namespace sitlnet::physics
