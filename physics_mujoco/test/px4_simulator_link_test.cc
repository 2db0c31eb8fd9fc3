// PX4 simulator messages and the TCP link, with a test client in PX4's place on loopback.
#include "physics_mujoco/px4_simulator_link.h"

#include <gtest/gtest.h>
#include <poll.h>

#include <cmath>
#include <memory>
#include <vector>

#include "physics_mujoco/px4_messages.h"
#include "physics_mujoco/test/fake_px4.h"

namespace sitlnet::physics {
namespace {

constexpr Ipv4 kLoopback{0x7F000001};

TEST(Px4MessagesTest, SensorUnitsAndFrames) {
  ImuSample imu;
  imu.accel_m_s2 = {0.5, 1, 9.81};  // FLU
  imu.gyro_rad_s = {0.1, 0.2, 0.3};
  const mavlink::HilSensor m = MakeHilSensor(1234567, imu, {0.2, 0.01, 0.43}, {955.5, 500, 11.9});
  EXPECT_EQ(m.time_usec, 1234u);  // ns -> us, rounded down
  EXPECT_FLOAT_EQ(m.xacc, 0.5f);  // FRD: y and z flip
  EXPECT_FLOAT_EQ(m.yacc, -1.0f);
  EXPECT_FLOAT_EQ(m.zacc, -9.81f);
  EXPECT_FLOAT_EQ(m.zgyro, -0.3f);
  EXPECT_FLOAT_EQ(m.xmag, 0.2f);
  EXPECT_FLOAT_EQ(m.abs_pressure, 955.5f);
  EXPECT_EQ(m.fields_updated, 0x1BFFu);  // all but DIFF_PRESSURE (0x400)
}

TEST(Px4MessagesTest, GpsUnits) {
  GpsFix fix;
  fix.position = {47.3977421, -8.5455944, 488.25};
  fix.velocity_ned_m_s = {-3, -4, 0.5};  // south-west
  fix.satellites = 10;
  const mavlink::HilGps m = MakeHilGps(5 * kNsPerS, fix, proto::Gps{});
  EXPECT_EQ(m.time_usec, 5000000u);
  EXPECT_EQ(m.lat, 473977421);
  EXPECT_EQ(m.lon, -85455944);
  EXPECT_EQ(m.alt, 488250);
  EXPECT_EQ(m.vel, 500);
  EXPECT_EQ(m.vn, -300);
  EXPECT_EQ(m.ve, -400);
  EXPECT_EQ(m.vd, 50);
  // Course: atan2(-4, -3) = 233.13 degrees.
  EXPECT_EQ(m.cog, 23313);
  EXPECT_EQ(m.fix_type, 3);
  EXPECT_EQ(m.eph, 100);
  fix.velocity_ned_m_s = {0, 0, 0};
  EXPECT_EQ(MakeHilGps(0, fix, proto::Gps{}).cog, mavlink::kUnknownU16);
}

TEST(Px4MessagesTest, MotorOutputsNeedTheArmedFlag) {
  mavlink::HilActuatorControls controls;
  controls.controls = {0.5f, 1.5f, -1.0f, 0.25f};
  controls.mode = 1;  // custom mode only: disarmed
  EXPECT_EQ(*RotorSpeedsOf(controls, 1000), (RotorSpeeds{0, 0, 0, 0}));
  controls.mode = 1 | mavlink::kModeFlagSafetyArmed;
  EXPECT_EQ(*RotorSpeedsOf(controls, 1000), (RotorSpeeds{500, 1000, 0, 250}));
  controls.controls[3] = NAN;
  EXPECT_FALSE(RotorSpeedsOf(controls, 1000).has_value());
}

// Polls the link until `done` holds, waiting on its sockets between polls (5 s at most).
template <typename Done>
void PollUntil(Px4SimulatorLink* link, Done done) {
  for (int i = 0; i < 100 && !done(); ++i) {
    pollfd fds[2] = {{link->listen_fd(), POLLIN, 0}, {link->connection_fd(), POLLIN, 0}};
    poll(fds, link->connection_fd() >= 0 ? 2 : 1, 50);
    link->Poll();
  }
  ASSERT_TRUE(done());
}

TEST(Px4SimulatorLinkTest, SensorsOutControlsInGarbageCountedReconnectResets) {
  Px4SimulatorLink link(kLoopback, 0, 1000, "test");
  EXPECT_EQ(link.Poll(), Px4SimulatorLink::Event::kNone);
  mavlink::HilSensor sensor;
  sensor.time_usec = 4000;
  link.Send(sensor, nullptr, nullptr);  // nobody connected yet
  EXPECT_EQ(link.counters().send_errors, 1u);

  auto px4 = std::make_unique<testing::FakePx4>(kLoopback, link.port());
  PollUntil(&link, [&] { return link.connected(); });
  EXPECT_EQ(link.counters().reconnections, 0u);

  mavlink::HilGps gps;
  gps.lat = 473977420;
  link.Send(sensor, &gps, nullptr);
  mavlink::HilSensor got_sensor;
  ASSERT_TRUE(mavlink::Unpack(px4->Receive(mavlink::kHilSensorId), &got_sensor));
  EXPECT_EQ(got_sensor.time_usec, 4000u);
  mavlink::HilGps got_gps;
  ASSERT_TRUE(mavlink::Unpack(px4->Receive(mavlink::kHilGpsId), &got_gps));
  EXPECT_EQ(got_gps.lat, 473977420);
  EXPECT_EQ(link.counters().heartbeats_sent, 1u);
  EXPECT_FALSE(link.answered_last_sensor());

  px4->Write({0x00, 0x55, 0xFD, 0x01});  // garbage between frames
  px4->SendControls(4000, 0.5f, true);
  PollUntil(&link, [&] { return link.counters().actuator_controls == 1; });
  EXPECT_TRUE(link.answered_last_sensor());
  EXPECT_TRUE(link.command().armed);
  EXPECT_TRUE(link.command().lockstep);
  EXPECT_EQ(link.command().rotor_speeds_rad_s, (RotorSpeeds{500, 500, 500, 500}));
  EXPECT_GE(link.counters().parser.bytes_skipped, 3u);

  // PX4 restarts: a new connection replaces the old one and asks for a reset.
  auto restarted = std::make_unique<testing::FakePx4>(kLoopback, link.port());
  Px4SimulatorLink::Event event = Px4SimulatorLink::Event::kNone;
  PollUntil(&link, [&] {
    if (event == Px4SimulatorLink::Event::kNone) event = link.Poll();
    return event != Px4SimulatorLink::Event::kNone;
  });
  EXPECT_EQ(event, Px4SimulatorLink::Event::kReconnected);
  EXPECT_EQ(link.counters().reconnections, 1u);
  EXPECT_FALSE(link.command().armed);  // motors stop until the new PX4 commands them
  EXPECT_EQ(link.command().rotor_speeds_rad_s, (RotorSpeeds{0, 0, 0, 0}));
  restarted.reset();
  PollUntil(&link, [&] { return !link.connected(); });
}

}  // namespace
}  // namespace sitlnet::physics
