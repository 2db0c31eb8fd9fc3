// The native protocol (docs/protocols.md): MotorCommand in, RobotState out on the robot's
// physics_port, periodic states at its state rate, the ESC failsafe, and the robot lock-step.
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "physics_mujoco/robot_codec.h"
#include "physics_mujoco/robot_link.h"

namespace sitlnet::physics {
namespace {

class NativeLink final : public RobotLink {
 public:
  NativeLink(const RobotLinkSetup& setup, TimeNs state_period_ns, TimeNs timeout_ns)
      : robot_(*setup.robot),
        world_(*setup.robot->world),
        robot_address_(setup.plan->ctl_robot_address),
        max_speed_rad_s_(setup.plan->airframe.max_rotor_speed_rad_s()),
        periodic_states_(setup.periodic_states),
        state_period_ns_(state_period_ns),
        next_state_ns_(state_period_ns),
        timeout_ns_(timeout_ns) {
    socket_ = UdpSocket::Bind(
        setup.plan->ctl_root_address,
        static_cast<uint16_t>(setup.scenario->spec.addresses().physics_port()), true, setup.who);
    setup.watch(this, socket_.fd());
  }

  void Poll() override {
    DrainDatagrams(socket_, [this](const uint8_t* data, ssize_t size, const sockaddr_in& from) {
      Handle(data, size, from);
    });
  }

  int StepsUntilDue() const override {
    TimeNs next = next_state_ns_;
    if (FailsafeArmed()) next = std::min(next, last_command_ns_ + timeout_ns_);
    return StepsUntil(next, world_.time_ns(robot_.robot), world_.step_ns());
  }

  void Serve() override {
    const TimeNs now = world_.time_ns(robot_.robot);
    if (FailsafeArmed() && now - last_command_ns_ >= timeout_ns_) {
      world_.SetRotorTarget(robot_.robot, RotorSpeeds{});  // ESC failsafe: motors spin down
      robot_.motors_cut = true;
      ++robot_.counters.failsafe_cuts;
    }
    if (now < next_state_ns_) return;
    while (next_state_ns_ <= now) next_state_ns_ += state_period_ns_;
    if (subscribed_ && periodic_states_) SendState();
  }

  bool spoke() const override { return robot_.counters.commands_accepted > 0; }

  void SendLockstepState() override {
    if (!InLockStep()) return;
    answered_state_ = false;
    SendState();
  }

  bool LockstepCommandMissing() const override {
    return InLockStep() &&
           (!answered_state_ || command_step_ != static_cast<uint64_t>(world_.steps(robot_.robot)));
  }

 private:
  bool InLockStep() const { return subscribed_ && !robot_.dropped; }
  bool FailsafeArmed() const { return has_command_ && !robot_.motors_cut && timeout_ns_ > 0; }

  void Handle(const uint8_t* data, ssize_t size, const sockaddr_in& from) {
    RobotCounters& counters = robot_.counters;
    if (SockaddrIpv4(from) != robot_address_) {
      ++counters.dropped_foreign_source;
      return;
    }
    DecodedCommand command;
    const CommandVerdict verdict =
        size > static_cast<ssize_t>(kReceiveBufferBytes)
            ? CommandVerdict::kMalformed
            : DecodeMotorCommand(data, size, robot_.robot, max_speed_rad_s_, &command);
    switch (verdict) {
      case CommandVerdict::kMalformed:
        ++counters.dropped_malformed;
        return;
      case CommandVerdict::kInvalid:
        ++counters.dropped_invalid;
        return;
      case CommandVerdict::kWrongRobot:
        ++counters.dropped_wrong_robot;
        return;
      case CommandVerdict::kAccepted:
        break;
    }
    if (robot_.dropped) {
      // Out of the lock-step for good: its motors stay cut (docs/physics.md).
      ++counters.dropped_after_drop;
      return;
    }
    ++counters.commands_accepted;
    world_.SetRotorTarget(robot_.robot, command.target_rad_s);
    has_command_ = true;
    robot_.motors_cut = false;
    last_command_ns_ = world_.time_ns(robot_.robot);
    command_step_ = command.step;
    answered_state_ = true;
    reply_ = from;
    subscribed_ = true;
  }

  void SendState() {
    const int robot = robot_.robot;
    world_.Lidar(robot, &lidar_);
    FillRobotState(robot, world_.steps(robot), world_.time_ns(robot), world_.Pose(robot),
                   world_.Imu(robot), lidar_, world_.rotor_speeds(robot), command_step_,
                   robot_.motors_cut, &state_);
    state_.SerializeToString(&wire_);
    robot_.Send(socket_, wire_, reply_);
    ++robot_.counters.states_sent;
  }

  RobotLinkContext& robot_;
  World& world_;
  Ipv4 robot_address_;
  double max_speed_rad_s_;
  bool periodic_states_;
  UdpSocket socket_;
  bool subscribed_ = false;  // A command came: states go to its source.
  sockaddr_in reply_{};
  bool has_command_ = false;
  TimeNs last_command_ns_ = 0;
  uint64_t command_step_ = 0;
  // Lock-step: a command arrived since the last SendLockstepState(). An announce sent before
  // the state (with the same step number) must not count as its answer.
  bool answered_state_ = false;
  TimeNs state_period_ns_;
  TimeNs next_state_ns_;
  TimeNs timeout_ns_;        // 0: failsafe off
  proto::RobotState state_;  // Reused buffers.
  std::string wire_;
  std::vector<float> lidar_;
};

}  // namespace

std::unique_ptr<RobotLink> MakeNativeLink(const RobotLinkSetup& setup) {
  const proto::Robot& spec = setup.plan->spec;
  if (!(std::isfinite(spec.state_rate_hz()) && spec.state_rate_hz() > 0)) {
    throw Error(setup.who + ": state_rate_hz must be > 0");
  }
  if (spec.command_timeout_ms() < 0) throw Error(setup.who + ": command_timeout_ms must be >= 0");
  const TimeNs state_period_ns =
      std::max<TimeNs>(1, std::llround(static_cast<double>(kNsPerS) / spec.state_rate_hz()));
  return std::make_unique<NativeLink>(setup, state_period_ns, spec.command_timeout_ms() * kNsPerMs);
}

}  // namespace sitlnet::physics
