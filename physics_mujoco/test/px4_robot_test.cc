// Px4Robot: a fake PX4 flies a World robot through the simulator link, lock-step style.
#include "physics_mujoco/px4_robot.h"

#include <gtest/gtest.h>
#include <poll.h>

#include "mavlink/mavlink.h"
#include "physics_mujoco/test/fake_px4.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

// Steps robot 0 one physics step at a time, like a driver holding the clock: at each step the
// robot's state goes out when due, and a due sensor message is answered before the next step.
class Px4RobotTest : public ::testing::Test {
 protected:
  // GPS fixes delivered the instant they are taken, so that counts follow the rate alone (the
  // default 110 ms delay is SensorModelsTest's).
  Scenario scenario_ = testing::MakeScenario(
      "robot { name: \"px4\" position_m { z: 0.2 } gps { delay_ms: 0 } }");
  GeodeticFrame frame_{scenario_.spec.geodetic_origin()};
  World world_{scenario_};
  Px4Robot robot_{scenario_, 0, 0, &frame_};

  void Connect(std::unique_ptr<testing::FakePx4>* px4) {
    *px4 = std::make_unique<testing::FakePx4>(scenario_.robots[0].ctl_root_address,
                                              robot_.link().port());
    ASSERT_TRUE(testing::WaitReadable(robot_.link().listen_fd(), 5000));
  }
};

TEST_F(Px4RobotTest, LockStepFlightAndRestart) {
  std::unique_ptr<testing::FakePx4> px4;
  Connect(&px4);
  TimeNs time_ns = 0;
  int sensors = 0;
  const TimeNs step_ns = world_.step_ns();
  // 2 s: PX4 arms at full throttle and answers each HIL_SENSOR with its time.
  for (; time_ns < 2 * kNsPerS; time_ns += step_ns) {
    if (robot_.Step(&world_, time_ns)) {
      ++sensors;
      mavlink::HilSensor sensor;
      ASSERT_TRUE(mavlink::Unpack(px4->Receive(mavlink::kHilSensorId), &sensor));
      ASSERT_EQ(sensor.time_usec, static_cast<uint64_t>(time_ns / kNsPerUs));
      px4->SendControls(sensor.time_usec, 1.0f, true);
      while (!robot_.link().answered_last_sensor()) {
        ASSERT_TRUE(testing::WaitReadable(robot_.link().connection_fd(), 5000));
        robot_.ApplyCommand(&world_);
      }
    }
    world_.Advance(1);
  }
  EXPECT_EQ(sensors, 500);                            // 250 Hz over 2 s
  EXPECT_EQ(robot_.link().counters().gps_sent, 20u);  // 10 Hz
  // Full throttle lifts the default airframe (13 N per rotor for 13 N of weight in all).
  EXPECT_GT(world_.Pose(0).position_m.z, 5);
  EXPECT_EQ(world_.rotor_target(0)[0], scenario_.robots[0].airframe.max_rotor_speed_rad_s());

  // PX4 restarts: the robot goes back to its start, motors stopped.
  std::unique_ptr<testing::FakePx4> restarted;
  Connect(&restarted);
  robot_.Step(&world_, time_ns);
  EXPECT_EQ(robot_.link().counters().reconnections, 1u);
  EXPECT_DOUBLE_EQ(world_.Pose(0).position_m.z, 0.2);
  EXPECT_EQ(world_.rotor_target(0)[0], 0);
  mavlink::HilSensor sensor;
  ASSERT_TRUE(mavlink::Unpack(restarted->Receive(mavlink::kHilSensorId), &sensor));
  EXPECT_EQ(sensor.time_usec, static_cast<uint64_t>(time_ns / kNsPerUs));
  mavlink::HilGps gps;
  ASSERT_TRUE(mavlink::Unpack(restarted->Receive(mavlink::kHilGpsId), &gps));
  EXPECT_EQ(gps.alt, 488200);  // origin 488 m + z 0.2 m
}

}  // namespace
}  // namespace sitlnet::physics
