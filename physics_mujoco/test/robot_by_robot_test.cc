// Lockstep without a fleet-wide barrier (issue 46, item 2; docs/physics.md, "Stepping an
// iteration"): with the frame gate, each robot steps as soon as its own autopilot has answered,
// not when every autopilot has. Fake autopilots (ArduPilot JSON clients and fake PX4s, in
// threads) play the autopilots over loopback.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <string>
#include <thread>
#include <vector>

#include "mavlink/mavlink.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/test/fake_px4.h"
#include "physics_mujoco/test/json_client.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

using testing::FakePx4;
using testing::Field;
using testing::FrameGate;
using testing::JsonClient;
using testing::MakeScenario;
using testing::ServoPacket16;
using testing::TakeSilentRobots;
using testing::TestJsonPort;
using testing::WaitReadable;

// Polls the server until `done`, for 10 s at most (false then).
template <typename Done>
bool PollUntil(PhysicsServer& server, Done done) {
  const TimeNs deadline_ns = MonotonicNowNs() + 10 * kNsPerS;
  while (!done()) {
    if (MonotonicNowNs() > deadline_ns) return false;
    if (WaitReadable(server.wait_fd(), 100)) server.Poll();
  }
  return true;
}

// The stepping order: robot a's autopilot answers at once, robot b's answers its first reply
// only once a has had every reply of the iteration. Behind a barrier at every step, a could
// not get its second reply before b answered: b would miss the gate's timeout. Without one, a
// steps through the iteration while b is held, then b does.
TEST(RobotByRobotTest, AnAnsweredRobotStepsOnWhileAnotherIsHeld) {
  const std::string port = std::to_string(TestJsonPort());
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 10 } ardupilot_json_port: " + port +
      " }\nrobot { name: \"b\" position_m { x: 5 z: 10 } ardupilot_json_port: " + port + " }");
  PhysicsServer server(scenario, FrameGate(2 * kNsPerS));
  JsonClient a("127.77.0.2", "127.77.0.1");
  JsonClient b("127.77.0.6", "127.77.0.5");
  a.Send(ServoPacket16(1000, 1, 1500));
  b.Send(ServoPacket16(1000, 1, 1500));
  ASSERT_TRUE(PollUntil(server, [&] {
    return server.counters(0).json_frames > 0 && server.counters(1).json_frames > 0;
  }));
  std::promise<void> a_at_end;
  std::vector<double> a_times_s, b_times_s;
  std::jthread a_answers([&] {
    for (uint32_t frame = 2; frame <= 10; ++frame) {  // Replies at 1..9 ms.
      const std::string reply = a.Receive(5000);
      if (reply.empty()) break;
      a_times_s.push_back(Field(reply, "timestamp")[0]);
      a.Send(ServoPacket16(1000, frame, 1500));
    }
    a_at_end.set_value();
  });
  std::jthread b_answers([&] {
    std::future<void> a_done = a_at_end.get_future();
    for (uint32_t frame = 2; frame <= 10; ++frame) {
      const std::string reply = b.Receive(5000);
      if (reply.empty()) return;
      b_times_s.push_back(Field(reply, "timestamp")[0]);
      if (frame == 2 && a_done.wait_for(std::chrono::seconds(5)) != std::future_status::ready) {
        return;
      }
      b.Send(ServoPacket16(1000, frame, 1500));
    }
  });
  const TimeNs begin_ns = MonotonicNowNs();
  server.Advance(10);
  const TimeNs took_ns = MonotonicNowNs() - begin_ns;
  a_answers.join();
  b_answers.join();
  EXPECT_TRUE(TakeSilentRobots(&server).empty()) << "b was not waited for, or a waited for b";
  EXPECT_LT(took_ns, 2 * kNsPerS) << "a barrier held a until b's gate timed out";
  ASSERT_EQ(a_times_s.size(), 9u);
  ASSERT_EQ(b_times_s.size(), 9u);
  for (int n = 1; n <= 9; ++n) {
    EXPECT_DOUBLE_EQ(a_times_s[n - 1], n / 1000.0) << n;
    EXPECT_DOUBLE_EQ(b_times_s[n - 1], n / 1000.0) << n;
  }
  EXPECT_EQ(server.world().steps(0), 10);
  EXPECT_EQ(server.world().steps(1), 10);
}

// An ArduPilot that flies on what it is told: its throttle is a function of each reply's
// altitude and climb rate, so any change in a reply's bytes changes the flight after it. Keeps
// every reply; stops after the one at `end_s` (due at the last iteration's end).
void FlyJson(JsonClient* client, uint16_t rate_hz, int slow_us, double end_s,
             std::string* replies) {
  for (uint32_t frame = 2;; ++frame) {
    const std::string reply = client->Receive(10000);
    if (reply.empty()) return;
    *replies += reply;
    if (Field(reply, "timestamp")[0] >= end_s - 1e-9) return;
    const double up_m = -Field(reply, "position")[2];
    const double climb_m_s = -Field(reply, "velocity")[2];
    const double pwm = std::clamp(1550 + 300 * (12 - up_m) - 100 * climb_m_s, 1100.0, 1900.0);
    // A slower autopilot: its robot falls behind the others within each iteration.
    if (slow_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(slow_us));
    client->Send(ServoPacket16(rate_hz, frame, static_cast<uint16_t>(pwm)));
  }
}

// The same for PX4: throttle from each HIL_SENSOR's barometric altitude and vertical specific
// force. Answers the sensors before `end_usec`.
void FlyPx4(FakePx4* px4, int slow_us, uint64_t end_usec) {
  float start_alt_m = 0;
  for (bool first = true;; first = false) {
    mavlink::HilSensor sensor;
    if (!mavlink::Unpack(px4->Receive(mavlink::kHilSensorId), &sensor)) return;
    if (sensor.time_usec >= end_usec) return;
    if (first) start_alt_m = sensor.pressure_alt;
    const float throttle = std::clamp(
        0.6f + 0.05f * (2 - (sensor.pressure_alt - start_alt_m)) + 0.002f * (sensor.zacc + 9.81f),
        0.2f, 0.9f);
    if (slow_us > 0) std::this_thread::sleep_for(std::chrono::microseconds(slow_us));
    px4->SendControls(sensor.time_usec, throttle, true);
  }
}

struct Flight {
  std::vector<std::string> received;  // Per autopilot: every byte the server sent it.
  std::vector<RobotPose> poses;       // Every robot's at the end.
};

// Three ArduPilots at 1000, 400 and 200 Hz (their replies fall on different steps), a PX4 at
// 250 Hz and a robot without autopilot fly 0.5 s, in iterations of `steps_per_advance` steps.
// The 400 Hz ArduPilot and the PX4 answer slowly.
Flight FlyFleet(int steps_per_advance) {
  const std::string port = std::to_string(TestJsonPort());
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 10 } ardupilot_json_port: " + port + " }\n" +
      "robot { name: \"b\" position_m { x: 5 z: 10 } ardupilot_json_port: " + port + " }\n" +
      "robot { name: \"c\" position_m { x: 10 z: 10 } ardupilot_json_port: " + port + " }\n" +
      "robot { name: \"d\" position_m { x: 15 z: 10 } px4_sim_port: " + port + " }\n" +
      "robot { name: \"e\" position_m { x: 20 z: 10 } }");
  PhysicsServer server(scenario, FrameGate(5 * kNsPerS));
  JsonClient a("127.77.0.2", "127.77.0.1");
  JsonClient b("127.77.0.6", "127.77.0.5");
  JsonClient c("127.77.0.10", "127.77.0.9");
  FakePx4 px4(scenario.robots[3].ctl_root_address, TestJsonPort());
  a.Send(ServoPacket16(1000, 1, 1500));
  b.Send(ServoPacket16(400, 1, 1500));
  c.Send(ServoPacket16(200, 1, 1500));
  // The clock starts once every autopilot has spoken (as `sitlnet run` waits for them).
  EXPECT_TRUE(PollUntil(server, [&] {
    return server.counters(0).json_frames > 0 && server.counters(1).json_frames > 0 &&
           server.counters(2).json_frames > 0 && server.px4_counters(3)->connections > 0;
  }));
  constexpr int kSteps = 500;  // 0.5 s of 1 ms steps: every autopilot's last reply ends there.
  Flight flight;
  flight.received.resize(4);
  {
    std::jthread fly_a(FlyJson, &a, 1000, 0, kSteps / 1000.0, &flight.received[0]);
    std::jthread fly_b(FlyJson, &b, 400, 300, kSteps / 1000.0, &flight.received[1]);
    std::jthread fly_c(FlyJson, &c, 200, 0, kSteps / 1000.0, &flight.received[2]);
    std::jthread fly_d(FlyPx4, &px4, 200, uint64_t{kSteps} * 1000);
    // PX4 is waited for once it has answered: the sensor of time 0, before the clock moves.
    server.Advance(0);
    EXPECT_TRUE(PollUntil(server, [&] { return server.px4_counters(3)->actuator_controls > 0; }));
    for (int step = 0; step < kSteps; step += steps_per_advance) server.Advance(steps_per_advance);
    server.Advance(0);  // What is due at the last iteration's end.
  }
  flight.received[3].assign(px4.received().begin(), px4.received().end());
  EXPECT_TRUE(TakeSilentRobots(&server).empty());
  for (int robot = 0; robot < 5; ++robot) {
    EXPECT_EQ(server.world().steps(robot), kSteps);
    flight.poses.push_back(server.world().Pose(robot));
  }
  return flight;
}

// The bytes: every message each autopilot got and every robot's flight are those of a barrier
// at every physics step (iterations of one step: every robot waits for every autopilot at each
// step, the strictest ordering), though here the autopilots answer at their own speeds within
// iterations of 10 steps.
TEST(RobotByRobotTest, AFleetAnsweringAtItsOwnSpeedsGetsTheBytesOfABarrierAtEveryStep) {
  const Flight barrier = FlyFleet(1);
  const Flight robot_by_robot = FlyFleet(10);
  const char* kAutopilots[] = {"1000 Hz ArduPilot", "400 Hz ArduPilot", "200 Hz ArduPilot",
                               "PX4"};
  for (int i = 0; i < 4; ++i) {
    EXPECT_GT(barrier.received[i].size(), 5000u) << kAutopilots[i];
    EXPECT_TRUE(barrier.received[i] == robot_by_robot.received[i])
        << kAutopilots[i] << ": " << barrier.received[i].size() << " and "
        << robot_by_robot.received[i].size() << " bytes";
  }
  for (int robot = 0; robot < 5; ++robot) {
    testing::ExpectSamePose(barrier.poses[robot], robot_by_robot.poses[robot],
                            "robot " + std::to_string(robot));
  }
  // The autopilots flew their robots (the robot without one falls from 10 m).
  for (int robot = 0; robot < 4; ++robot) {
    EXPECT_GT(std::abs(barrier.poses[robot].position_m.z - 10), 0.01) << robot;
  }
}

}  // namespace
}  // namespace sitlnet::physics
