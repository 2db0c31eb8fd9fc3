// ArduPilot's JSON SITL backend on the robot's ardupilot_json_port (docs/protocols.md): a servo
// frame asks for the state at the frame's end; the reply waits until the world's clock has
// reached that time. Packet format and frame counting: ardupilot_json.h.
#include <algorithm>
#include <limits>
#include <memory>
#include <optional>

#include "clock/clock.h"
#include "physics_mujoco/ardupilot_json.h"
#include "physics_mujoco/robot_link.h"

namespace sitlnet::physics {
namespace {

// How far behind the world's clock SITL's may fall in realtime pacing and still catch up frame
// by frame (docs/protocols.md). Behind by more, SITL is not keeping up rather than briefly
// delayed, and its clock jumps to the world's.
int64_t MaxCatchUpSteps(const World& world) { return 100 * kNsPerMs / world.step_ns(); }

class ArduPilotJsonLink final : public RobotLink {
 public:
  ArduPilotJsonLink(const RobotLinkSetup& setup, uint16_t port)
      : robot_(*setup.robot),
        world_(*setup.robot->world),
        robot_address_(setup.plan->ctl_robot_address),
        max_speed_rad_s_(setup.plan->airframe.max_rotor_speed_rad_s()) {
    socket_ =
        UdpSocket::Bind(setup.plan->ctl_root_address, port, true, setup.who + " (ArduPilot JSON)");
    setup.watch(this, socket_.fd());
  }

  void Poll() override {
    DrainDatagrams(socket_, [this](const uint8_t* data, ssize_t size, const sockaddr_in& from) {
      Handle(data, size, from);
    });
  }

  int StepsUntilDue() const override {
    if (!pending_) return std::numeric_limits<int>::max();
    return static_cast<int>(std::clamp<int64_t>(due_steps_ - world_.steps(robot_.robot), 1,
                                                std::numeric_limits<int>::max()));
  }

  // Sends the state of a pending frame once the world's clock has reached the frame's end.
  void Serve() override {
    if (!DueNow()) return;
    pending_ = false;
    const int robot = robot_.robot;
    // The reply carries the frame's end; in realtime pacing a late frame's end lies behind the
    // world's clock (SITL catching up), the state is the world's now.
    const TimeNs reply_time_ns =
        world_.time_ns(robot) - (world_.steps(robot) - due_steps_) * world_.step_ns();
    start_steps_ = due_steps_;
    FormatJsonStateInto(reply_time_ns, world_.Pose(robot), world_.Imu(robot), &last_reply_);
    robot_.Send(socket_, last_reply_, reply_to_);
  }

  bool spoke() const override { return robot_.counters.json_frames > 0; }
  // An ArduPilot robot gets no more replies until SITL restarts.
  void OnDropped() override { pending_ = false; }

  bool paced() const override { return true; }
  bool DueNow() const override { return pending_ && world_.steps(robot_.robot) >= due_steps_; }
  // A frame answering the last reply (SITL has sent a frame before).
  bool AnswerOutstanding() const override { return joined_ && !pending_ && !robot_.dropped; }
  UnansweredMessage unanswered() const override {
    return {"its JSON reply", "with a servo frame"};
  }

 private:
  void Handle(const uint8_t* data, ssize_t size, const sockaddr_in& from) {
    RobotCounters& counters = robot_.counters;
    const auto packet = size <= static_cast<ssize_t>(kReceiveBufferBytes)
                            ? ParseServoPacket(data, size)
                            : std::nullopt;
    if (SockaddrIpv4(from) != robot_address_ || !packet) {
      ++counters.json_dropped;
      return;
    }
    uint64_t missed = 0;
    const FrameAction action = tracker_.OnFrame(packet->frame_count, &missed);
    if (action == FrameAction::kResend) {
      // SITL repeats a frame whose reply it has not seen: the reply already sent goes again; one
      // not yet due will go when it is.
      ++counters.json_resends;
      if (!pending_ && !last_reply_.empty()) robot_.Send(socket_, last_reply_, from);
      return;
    }
    if (action == FrameAction::kRestart) {
      // SITL restarted: the vehicle starts over where it began, at the world's current time,
      // and the robot rejoins the lock-step if it had been dropped.
      ++counters.json_restarts;
      world_.ResetRobot(robot_.robot);
      rate_hz_ = 0;
      robot_.Rejoin();
    }
    if (robot_.dropped) {
      ++counters.dropped_after_drop;
      return;
    }
    ++counters.json_frames;
    counters.json_missed_frames += missed;
    world_.SetRotorTarget(robot_.robot, PwmToRotorSpeeds(*packet, max_speed_rad_s_));
    const int64_t now_steps = world_.steps(robot_.robot);
    if (!joined_ || action == FrameAction::kRestart) start_steps_ = now_steps;
    if (packet->frame_rate_hz != rate_hz_) {  // new rate: count frames from here
      rate_hz_ = packet->frame_rate_hz;
      base_steps_ = now_steps;
      frames_ = 0;
    }
    ++frames_;
    // The rate SITL asks for, at most a frame per physics step (a shorter frame ends a step
    // after it starts, below): ArduCopter's 1200 Hz is served at 1000 with the 1 ms step.
    robot_.answers.Answered(
        1, std::min(static_cast<double>(rate_hz_), static_cast<double>(kNsPerS) / world_.step_ns()),
        MonotonicNowNs());
    // Frame n ends at n / frame_rate: whole physics steps, the remainder carried (exact over
    // many frames when 1/frame_rate is not a multiple of the step).
    int64_t due_steps = base_steps_ + clock::TickTimeNs(frames_, rate_hz_) / world_.step_ns();
    if (due_steps < now_steps - MaxCatchUpSteps(world_)) {
      // Late by more than SITL may catch up (realtime pacing, SITL slower than the clock for a
      // while): its clock jumps to now, and frames count from here.
      ++counters.json_clock_jumps;
      base_steps_ += now_steps - due_steps;
      due_steps = now_steps;
    }
    // Late by less (realtime pacing, SITL was not given the CPU in time): the frame is answered
    // at once with its own end, and so are the next ones until SITL's clock is the world's
    // again. Every frame still ends 1 / frame_rate after the last: SITL's main loop keeps its
    // rate in its own clock, which a jump would break ("Main loop slow", issue 31).
    if (due_steps <= start_steps_) {
      // A frame shorter than what is left of the step: it still ends a step after it starts.
      // SITL takes a reply with the last one's timestamp as no time passed (SIM_JSON's dt = 0):
      // its clock stands and it sends the next frame at once, each with frame_rate one higher
      // (it steers towards SIM_RATE_HZ, 1200), which restarted the count above, so the next
      // frame was due at once again: 200 frames per step. Frames count from here.
      due_steps = start_steps_ + 1;
      base_steps_ = due_steps;
      frames_ = 0;
    }
    due_steps_ = due_steps;
    pending_ = true;
    joined_ = true;
    Unmute();  // Answering again.
    reply_to_ = from;
    Serve();
  }

  RobotLinkContext& robot_;
  World& world_;
  Ipv4 robot_address_;
  double max_speed_rad_s_;
  UdpSocket socket_;
  FrameTracker tracker_;
  std::string last_reply_;
  sockaddr_in reply_to_{};
  uint16_t rate_hz_ = 0;
  int64_t base_steps_ = 0;  // Frames at rate_hz_ are counted from this step.
  int64_t frames_ = 0;
  bool joined_ = false;   // Sent a frame: the frame gate waits for its next one.
  bool pending_ = false;  // A frame's reply is due at due_steps_.
  int64_t due_steps_ = 0;
  // Where the next frame starts: the last frame's end (its reply), or where the first frame
  // came (at start, after a restart). A frame ends at least one step after it.
  int64_t start_steps_ = 0;
};

}  // namespace

std::unique_ptr<RobotLink> MakeArduPilotJsonLink(const RobotLinkSetup& setup) {
  const uint32_t port = setup.plan->spec.ardupilot_json_port();
  if (port > 65535 || port == setup.scenario->spec.addresses().physics_port()) {
    throw Error(setup.who +
                ": ardupilot_json_port must be in [1, 65535] and differ from physics_port");
  }
  if (port == 0) return nullptr;
  return std::make_unique<ArduPilotJsonLink>(setup, static_cast<uint16_t>(port));
}

}  // namespace sitlnet::physics
