// PX4 robots in the PhysicsServer (issue 14, item 2): the server sends each connected PX4 its
// HIL_SENSOR every 4 ms of the world's clock and, with the frame gate (lockstep pacing), does not
// move the clock past a HIL_SENSOR before PX4's HIL_ACTUATOR_CONTROLS answering it arrived, as
// PX4's lock-step with Gazebo works. A fake PX4 (test/fake_px4.h) plays PX4's side.
#include <gtest/gtest.h>

#include <atomic>
#include <memory>
#include <thread>
#include <vector>

#include "mavlink/mavlink.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/px4_simulator_link.h"
#include "physics_mujoco/test/fake_px4.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

using testing::FakePx4;
using testing::MakeScenario;
using testing::TestJsonPort;
using testing::WaitReadable;

class Px4ServerTest : public ::testing::Test {
 protected:
  Scenario scenario_ = MakeScenario(
      "robot { name: \"px4\" position_m { x: 1 z: 0.2 } px4_sim_port: " +
      std::to_string(TestJsonPort()) + " }\nrobot { name: \"b\" position_m { x: 5 z: 0.2 } }");
  // The frame gate (lockstep pacing) at 5 s; a test may make the server again with another.
  std::unique_ptr<PhysicsServer> server_ =
      std::make_unique<PhysicsServer>(scenario_, testing::FrameGate(5 * kNsPerS));
  void Gate(TimeNs timeout_ns) {
    server_.reset();
    server_ = std::make_unique<PhysicsServer>(scenario_, testing::FrameGate(timeout_ns));
  }

  // A fake PX4 connected and seen by the server (as `sitlnet run` waits for it).
  std::unique_ptr<FakePx4> Connect() {
    auto px4 = std::make_unique<FakePx4>(scenario_.robots[0].ctl_root_address, TestJsonPort());
    const uint64_t before = server_->px4_counters(0)->connections;
    EXPECT_TRUE(PollUntil([&] { return server_->px4_counters(0)->connections > before; }))
        << "the connection is not seen";
    return px4;
  }

  // PX4's lock-step from a thread: answers `sensors` HIL_SENSORs with `throttle`, keeping their
  // times. Join before reading them.
  // Polls the server until `done`, for 10 s at most (false then).
  template <typename Done>
  bool PollUntil(Done done) {
    const TimeNs deadline_ns = MonotonicNowNs() + 10 * kNsPerS;
    while (!done()) {
      if (MonotonicNowNs() > deadline_ns) return false;
      if (WaitReadable(server_->wait_fd(), 100)) server_->Poll();
    }
    return true;
  }

  // jthread: joined also when an ASSERT leaves the test early.
  std::jthread Answer(FakePx4* px4, int sensors, float throttle, std::vector<uint64_t>* times) {
    return std::jthread([=] {
      for (int i = 0; i < sensors; ++i) {
        mavlink::HilSensor sensor;
        if (!mavlink::Unpack(px4->Receive(mavlink::kHilSensorId), &sensor)) return;
        times->push_back(sensor.time_usec);
        px4->SendControls(sensor.time_usec, throttle, true);
      }
    });
  }

  // Steps `iterations` iterations of 10 steps; true if every sensor sent in each was answered
  // before the clock moved past it.
  bool EverySensorAnsweredIn(int iterations) {
    bool answered = true;
    for (int iteration = 0; iteration < iterations; ++iteration) {
      server_->Advance(10);
      const Px4Counters counters = *server_->px4_counters(0);
      answered &= counters.actuator_controls == counters.sensors_sent;
    }
    return answered;
  }
};

TEST_F(Px4ServerTest, TheClockWaitsForEachAnswerAndSensorsFollowTheWorldsClock) {
  std::unique_ptr<FakePx4> px4 = Connect();
  constexpr int kSensors = 250;  // 1 s at 250 Hz
  std::vector<uint64_t> sensor_usec;
  std::jthread autopilot = Answer(px4.get(), kSensors, 0.8f, &sensor_usec);
  // PX4 is awaited once it has answered (as with Gazebo): the sensor of time 0 goes out at the
  // first iteration's start, and its answer comes before the clock moves.
  server_->Advance(0);
  ASSERT_TRUE(PollUntil([&] { return server_->px4_counters(0)->actuator_controls > 0; }));
  const bool every_sensor_answered = EverySensorAnsweredIn(100);
  autopilot.join();
  EXPECT_TRUE(every_sensor_answered);
  EXPECT_TRUE(testing::TakeSilentRobots(server_.get()).empty());
  ASSERT_EQ(sensor_usec.size(), static_cast<size_t>(kSensors));
  for (int k = 0; k < kSensors; ++k) EXPECT_EQ(sensor_usec[k], 4000u * k) << k;
  EXPECT_EQ(server_->world().steps(0), 1000);
  EXPECT_EQ(server_->world().steps(1), 1000);
  EXPECT_GT(server_->world().Pose(0).position_m.z, 1);  // 0.8 throttle lifts it
  // PX4 restarts: the robot is back at its start while the clock goes on, and PX4 gets the
  // sensors of the current time.
  std::unique_ptr<FakePx4> restarted = Connect();
  EXPECT_EQ(server_->px4_counters(0)->reconnections, 1u);
  EXPECT_DOUBLE_EQ(server_->world().Pose(0).position_m.z, 0.2);
  server_->Advance(0);  // The next iteration's start: the sensor due at 1 s leaves.
  mavlink::HilSensor sensor;
  ASSERT_TRUE(mavlink::Unpack(restarted->Receive(mavlink::kHilSensorId), &sensor));
  EXPECT_EQ(sensor.time_usec, 1000000u);
}

TEST_F(Px4ServerTest, ASilentPx4IsReportedOnceAndNotWaitedForAgain) {
  Gate(50 * kNsPerMs);
  std::unique_ptr<FakePx4> px4 = Connect();
  server_->Advance(0);  // The sensor of time 0: answered, then PX4 falls silent.
  mavlink::HilSensor sensor;
  ASSERT_TRUE(mavlink::Unpack(px4->Receive(mavlink::kHilSensorId), &sensor));
  px4->SendControls(sensor.time_usec, 0.5f, true);
  ASSERT_TRUE(PollUntil([&] { return server_->px4_counters(0)->actuator_controls > 0; }));
  server_->Advance(10);
  // Named in PX4's words, for the run's message (physics_side).
  const std::vector<SilentAutopilot> silent = server_->TakeSilentAutopilots();
  ASSERT_EQ(silent.size(), 1u);
  EXPECT_EQ(silent[0].robot, 0);
  EXPECT_EQ(silent[0].unanswered, "its HIL_SENSOR");
  EXPECT_EQ(silent[0].expected, "with HIL_ACTUATOR_CONTROLS");
  const TimeNs begin_ns = MonotonicNowNs();
  server_->Advance(10);
  EXPECT_LT(MonotonicNowNs() - begin_ns, 50 * kNsPerMs);  // Not waited for again.
  EXPECT_TRUE(testing::TakeSilentRobots(server_.get()).empty());
  EXPECT_EQ(server_->world().steps(0), 20);
}

// PX4 dies in lock-step (its connection closes): the clock waits for it as for a silent PX4 and
// reports it once (the caller's on_silent_robot then stops the run or drops the robot); PX4
// started again connects, and the robot, back at its start, is in the lock-step again.
TEST_F(Px4ServerTest, APx4ThatDiesIsReportedSilentAndRejoinsWhenItConnectsAgain) {
  Gate(50 * kNsPerMs);
  auto px4 = Connect();
  server_->Advance(0);
  mavlink::HilSensor sensor;
  ASSERT_TRUE(mavlink::Unpack(px4->Receive(mavlink::kHilSensorId), &sensor));
  px4->SendControls(sensor.time_usec, 0.5f, true);
  ASSERT_TRUE(PollUntil([&] { return server_->px4_counters(0)->actuator_controls > 0; }));
  px4.reset();  // PX4 dies.
  const TimeNs begin_ns = MonotonicNowNs();
  server_->Advance(10);
  EXPECT_GE(MonotonicNowNs() - begin_ns, 50 * kNsPerMs);  // Waited for, up to the timeout.
  EXPECT_EQ(testing::TakeSilentRobots(server_.get()), std::vector<int>{0});
  server_->Advance(10);
  EXPECT_TRUE(testing::TakeSilentRobots(server_.get()).empty());  // Reported once.
  // PX4 again (its connection may get the dead one's fd number): answers every sensor from now
  // on, and the clock waits for each answer.
  px4 = Connect();
  EXPECT_DOUBLE_EQ(server_->world().Pose(0).position_m.z, 0.2);
  std::vector<uint64_t> sensor_usec;
  std::jthread autopilot = Answer(px4.get(), 23, 0.8f, &sensor_usec);  // 20, 24, ..., 108 ms
  server_->Advance(0);
  ASSERT_TRUE(PollUntil([&] { return server_->px4_counters(0)->actuator_controls >= 2; }))
      << "the answer is not seen";
  const bool every_sensor_answered = EverySensorAnsweredIn(9);
  autopilot.join();
  EXPECT_TRUE(every_sensor_answered);
  EXPECT_TRUE(testing::TakeSilentRobots(server_.get()).empty());
  EXPECT_EQ(sensor_usec.front(), 20000u);
}

}  // namespace
}  // namespace sitlnet::physics
