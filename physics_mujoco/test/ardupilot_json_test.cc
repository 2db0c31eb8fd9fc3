// ArduPilot JSON SITL backend, exercised by a client written from ArduPilot's protocol
// description (libraries/SITL/examples/JSON/readme.md), over UDP on loopback. The client plays
// ArduPilot: it sends a servo frame and waits for the reply, whose timestamp is its clock; the
// server replies when the world's clock reaches the frame's end (docs/protocols.md).
#include "physics_mujoco/ardupilot_json.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <cstdlib>
#include <numbers>
#include <thread>
#include <utility>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/test/json_client.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

using testing::Field;
using testing::FrameGate;
using testing::JsonClient;
using testing::MakeScenario;
using testing::ServoPacket16;
using testing::TakeSilentRobots;
using testing::TestJsonPort;
using testing::WaitReadable;

// Sends one packet and returns its reply, driving the server on this thread as a clock would:
// the packet is handled, then the world advances a step at a time until the reply is out (at
// most `max_steps`; "" if none came).
std::string Exchange(PhysicsServer& server, JsonClient& client, const std::string& packet,
                     int max_steps = 100) {
  client.Send(packet);
  if (!WaitReadable(server.wait_fd(), 2000)) return "";
  server.Poll();
  for (int step = 0; step <= max_steps; ++step) {
    if (WaitReadable(client.fd(), 0)) return client.Receive();
    server.Advance(1);
  }
  return "";
}

// Exchange with the frame gate on: the reply due at the end of an Advance leaves at the start
// of the next, so the world advances the frame's one step, then Advance(0) sends the reply.
std::string GatedExchange(PhysicsServer& server, JsonClient& client, const std::string& packet) {
  client.Send(packet);
  if (!WaitReadable(server.wait_fd(), 2000)) return "";
  server.Poll();
  server.Advance(1);
  server.Advance(0);
  return client.Receive();
}

class ArduPilotJsonTest : public ::testing::Test {
 protected:
  ArduPilotJsonTest()
      : scenario_(MakeScenario("robot { name: \"a\" position_m { x: 1 y: 2 z: 10 } "
                               "ardupilot_json_port: " +
                               std::to_string(TestJsonPort()) + " }")),
        server_(scenario_) {}

  std::string Exchange(const std::string& packet) {
    return physics::Exchange(server_, client_, packet);
  }

  Scenario scenario_;
  PhysicsServer server_;
  JsonClient client_{"127.77.0.2"};
};

TEST_F(ArduPilotJsonTest, EachNewFrameAdvancesOneOverFrameRate) {
  const std::string first = Exchange(ServoPacket16(1000, 1, 1000));
  ASSERT_FALSE(first.empty());
  EXPECT_EQ(first.front(), '\n');
  EXPECT_EQ(first.back(), '\n');
  EXPECT_EQ(first.find(' '), std::string::npos);  // keys written without spaces
  EXPECT_DOUBLE_EQ(Field(first, "timestamp")[0], 0.001);
  EXPECT_DOUBLE_EQ(Field(Exchange(ServoPacket16(1000, 2, 1000)), "timestamp")[0], 0.002);
  // 400 Hz is 2.5 ms a frame: whole 1 ms steps, remainder carried, exact every 2 frames.
  EXPECT_NEAR(Field(Exchange(ServoPacket16(400, 3, 1000)), "timestamp")[0], 0.004, 1e-12);
  EXPECT_NEAR(Field(Exchange(ServoPacket16(400, 4, 1000)), "timestamp")[0], 0.007, 1e-12);
  EXPECT_EQ(server_.counters(0).json_frames, 4u);
}

// ArduCopter's SITL asks for 1200 Hz (SIM_RATE_HZ), then for 1/dt of the replies it gets, one
// higher each frame after a reply that did not advance its clock (SIM_JSON.cpp: recv_fdm,
// update). A frame shorter than the 1 ms step still ends a step after the last reply: each
// reply advances its clock, whatever the rate, also when the rate changes every frame (before,
// such a frame was answered at once with the last timestamp, 200 frames per step).
TEST_F(ArduPilotJsonTest, AFrameShorterThanAStepEndsAStepAfterTheLastReply) {
  uint32_t count = 0;
  double last_s = 0;
  for (const uint16_t rate : {1200, 1001, 1002, 1003, 1200, 1200, 1200, 1001, 1001}) {
    const std::string reply = Exchange(ServoPacket16(rate, ++count, 1000));
    ASSERT_FALSE(reply.empty()) << "frame " << count;
    EXPECT_NEAR(Field(reply, "timestamp")[0], last_s + 0.001, 1e-12) << "frame " << count;
    last_s = Field(reply, "timestamp")[0];
    // SITL is paced by the replies alone, not by its own wall clock as well.
    EXPECT_EQ(Field(reply, "no_time_sync"), std::vector<double>{1});
  }
}

// Realtime pacing, SITL late (the host gave it no CPU for 50 ms): each late frame is answered at
// once with its own end, 1 / frame_rate after the last, until SITL's clock is the world's
// again. A reply at the world's now would jump SITL's clock, and its main loop would run fewer
// times per second of its clock ("Main loop slow", issue 31).
TEST_F(ArduPilotJsonTest, ALateFrameIsAnsweredAtOnceWithItsOwnEndUntilSitlCatchesUp) {
  ASSERT_DOUBLE_EQ(Field(Exchange(ServoPacket16(400, 1, 1500)), "timestamp")[0], 0.002);
  server_.Advance(50);  // The world's clock: 52 ms.
  std::vector<double> replies_s;
  // Frames 2 to 21 end at 5 to 52 ms: each is due when it comes (no step is taken).
  for (uint32_t frame = 2; frame <= 21; ++frame) {
    const std::string reply =
        physics::Exchange(server_, client_, ServoPacket16(400, frame, 1500), 0);
    ASSERT_FALSE(reply.empty()) << "frame " << frame;
    replies_s.push_back(Field(reply, "timestamp")[0]);
  }
  for (uint32_t frame = 2; frame <= 21; ++frame) {
    EXPECT_NEAR(replies_s[frame - 2], std::floor(frame * 2.5) / 1000, 1e-12) << "frame " << frame;
  }
  EXPECT_EQ(server_.world().steps(0), 52);  // Caught up without the world moving.
  // Frame 22 ends at 55 ms, ahead of the world: answered when the world gets there.
  EXPECT_DOUBLE_EQ(Field(Exchange(ServoPacket16(400, 22, 1500)), "timestamp")[0], 0.055);
  EXPECT_EQ(server_.counters(0).json_clock_jumps, 0u);
}

// Behind by more than SITL may catch up (100 ms): its clock jumps to the world's, counted.
TEST_F(ArduPilotJsonTest, AFrameLateByMoreThan100MsJumpsToTheWorldsClock) {
  ASSERT_DOUBLE_EQ(Field(Exchange(ServoPacket16(400, 1, 1500)), "timestamp")[0], 0.002);
  server_.Advance(150);  // 152 ms: frame 2 (5 ms) is 147 ms late.
  EXPECT_DOUBLE_EQ(Field(Exchange(ServoPacket16(400, 2, 1500)), "timestamp")[0], 0.152);
  EXPECT_EQ(server_.counters(0).json_clock_jumps, 1u);
  // Frames count from there again.
  EXPECT_DOUBLE_EQ(Field(Exchange(ServoPacket16(400, 3, 1500)), "timestamp")[0], 0.154);
}

TEST_F(ArduPilotJsonTest, RepeatedFrameCountResendsWithoutAdvancing) {
  Exchange(ServoPacket16(1000, 7, 1000));
  const std::string reply = Exchange(ServoPacket16(1000, 8, 1000));
  const std::string again = Exchange(ServoPacket16(1000, 8, 1000));
  EXPECT_EQ(again, reply);
  EXPECT_EQ(server_.world().steps(0), 2);
  EXPECT_EQ(server_.counters(0).json_resends, 1u);
  // A jump counts the missed frames and still advances one frame.
  EXPECT_DOUBLE_EQ(Field(Exchange(ServoPacket16(1000, 11, 1000)), "timestamp")[0], 0.003);
  EXPECT_EQ(server_.counters(0).json_missed_frames, 2u);
}

TEST_F(ArduPilotJsonTest, SmallerFrameCountRestartsTheVehicleAndTheClockGoesOn) {
  for (uint32_t frame = 100; frame < 400; ++frame) Exchange(ServoPacket16(1000, frame, 1000));
  EXPECT_LT(server_.world().Pose(0).position_m.z, 10 - 0.1);  // fell with motors off
  const std::string reply = Exchange(ServoPacket16(1000, 1, 1000));
  EXPECT_EQ(server_.counters(0).json_restarts, 1u);
  // The world has one clock: the restarted vehicle's first frame ends one step after now.
  EXPECT_DOUBLE_EQ(Field(reply, "timestamp")[0], 0.301);
  // Back at the start: ENU (1, 2, 10) is NED (2, 1, -10), minus one step of fall.
  const auto position = Field(reply, "position");
  ASSERT_EQ(position.size(), 3u);
  EXPECT_DOUBLE_EQ(position[0], 2);
  EXPECT_DOUBLE_EQ(position[1], 1);
  EXPECT_NEAR(position[2], -10, 1e-4);
}

TEST_F(ArduPilotJsonTest, FieldsAreInNedAndFrd) {
  // The robot starts with yaw 0 (nose east): NED quaternion is a +90 deg turn about down.
  const std::string reply = Exchange(ServoPacket16(1000, 1, 1000));
  const auto q = Field(reply, "quaternion");
  ASSERT_EQ(q.size(), 4u);
  EXPECT_NEAR(q[0], std::sqrt(0.5), 1e-9);
  EXPECT_NEAR(q[3], std::sqrt(0.5), 1e-9);
  // Falling: velocity down (NED z) positive after one 1 ms step, g * dt.
  EXPECT_NEAR(Field(reply, "velocity")[2], 9.81 * 0.001, 1e-9);
  // Free fall: the accelerometer measures nothing.
  EXPECT_NEAR(Field(reply, "accel_body")[2], 0, 1e-6);
  EXPECT_EQ(Field(reply, "gyro").size(), 3u);
}

TEST(ArduPilotJsonRestTest, AccelBodyReadsMinusGAtRestOnTheGround) {
  // Collision box half height 0.25 * 0.14 = 0.035 m: resting on the ground.
  const Scenario scenario =
      MakeScenario("robot { name: \"a\" position_m { z: 0.035 } ardupilot_json_port: " +
                   std::to_string(TestJsonPort()) + " }");
  PhysicsServer server(scenario);
  JsonClient client("127.77.0.2");
  std::string reply;
  for (uint32_t frame = 1; frame <= 500; ++frame) {
    reply = Exchange(server, client, ServoPacket16(1000, frame, 1000));
    ASSERT_FALSE(reply.empty());
  }
  // readme: accel_body reads about (0, 0, -9.81) at rest (FRD: gravity's reaction is up = -z).
  EXPECT_NEAR(Field(reply, "accel_body")[2], -9.81, 0.01);
  EXPECT_NEAR(Field(reply, "position")[2], -0.035, 0.005);
}

TEST_F(ArduPilotJsonTest, BadPacketsAreDroppedAndCounted) {
  std::string bad_magic = ServoPacket16(1000, 1, 1000);
  bad_magic[0] = 0;
  client_.Send(bad_magic);
  client_.Send(ServoPacket16(1000, 1, 1000).substr(0, 39));
  client_.Send(ServoPacket16(0, 1, 1000));  // frame_rate 0
  // Issue 17, finding 9: 1 Hz would advance 1000 physics steps in one packet; below 50 Hz is
  // refused (it used to be accepted and stepped).
  client_.Send(ServoPacket16(1, 1, 1000));
  client_.Send(ServoPacket16(kMinJsonFrameRateHz - 1, 1, 1000));
  JsonClient stranger("127.77.0.9");
  stranger.Send(ServoPacket16(1000, 1, 1000));
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (server_.counters(0).json_dropped < 6 && MonotonicNowNs() < deadline) {
    if (WaitReadable(server_.wait_fd(), 100)) server_.Poll();
  }
  EXPECT_EQ(server_.counters(0).json_dropped, 6u);
  EXPECT_EQ(server_.world().steps(0), 0);
  EXPECT_FALSE(Exchange(ServoPacket16(1000, 1, 1000)).empty());
}

// ArduPilot in the world's clock (issue 14): in lockstep pacing the frame gate holds the clock
// at each reply until the frame answering it has come, so every reply leaves exactly at its
// frame's end, whatever the client's (wall) speed, and the ArduPilot robot and a native robot
// beside it share one clock. Without the gate the world runs past replies that have not been
// answered: frames arrive late and the replies' times leave the 400 Hz grid.
TEST(ArduPilotJsonGateTest, TheClockWaitsForEachFrameAndRepliesLeaveAtTheirFramesEnd) {
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 10 } ardupilot_json_port: " +
      std::to_string(TestJsonPort()) + " }\nrobot { name: \"b\" position_m { x: 5 z: 10 } }");
  PhysicsServer server(scenario, FrameGate(5 * kNsPerS));
  JsonClient client("127.77.0.2");
  constexpr int kFrames = 400;  // 1 s at 400 Hz
  std::vector<double> reply_times_s;
  std::thread ardupilot([&] {
    client.Send(ServoPacket16(400, 1, 1600));
    for (uint32_t frame = 2; frame <= kFrames + 1; ++frame) {
      const std::string reply = client.Receive(10000);
      if (reply.empty()) return;
      reply_times_s.push_back(Field(reply, "timestamp")[0]);
      client.Send(ServoPacket16(400, frame, 1600));
    }
  });
  // The clock starts once the autopilot has spoken (as `sitlnet run` waits for it).
  while (server.counters(0).json_frames == 0) {
    if (WaitReadable(server.wait_fd(), 10000)) server.Poll();
  }
  for (int iteration = 0; iteration < 100; ++iteration) server.Advance(10);  // 1 s
  // A reply due at an Advance's end leaves at the start of the next (the next iteration's).
  server.Advance(0);
  ardupilot.join();
  server.Poll();  // Its last frame, sent before it ended.
  EXPECT_TRUE(TakeSilentRobots(&server).empty());
  ASSERT_EQ(reply_times_s.size(), static_cast<size_t>(kFrames));
  for (int n = 1; n <= kFrames; ++n) {
    // Frame n ends at n * 2.5 ms, in whole 1 ms steps with the remainder carried (2, 5, 7, ...).
    EXPECT_NEAR(reply_times_s[n - 1], std::floor(n * 2.5) / 1000, 1e-12) << "frame " << n;
  }
  EXPECT_EQ(server.world().steps(0), 1000);
  EXPECT_EQ(server.world().steps(1), 1000);
  EXPECT_EQ(server.counters(0).json_frames, static_cast<uint64_t>(kFrames + 1));
  EXPECT_EQ(server.counters(0).json_resends, 0u);
}

// A silent autopilot (lockstep): after the gate's timeout the clock goes on without it and it is
// reported once, for the scenario's policy; dropped, its frames are refused until SITL restarts
// (a smaller frame_count), which puts the vehicle back at its start in the lock-step again.
TEST(ArduPilotJsonGateTest, ASilentAutopilotIsReportedOnceAndARestartRejoins) {
  const Scenario scenario =
      MakeScenario("robot { name: \"a\" position_m { x: 1 z: 10 } ardupilot_json_port: " +
                   std::to_string(TestJsonPort()) + " }");
  PhysicsServer server(scenario, FrameGate(50 * kNsPerMs));
  JsonClient client("127.77.0.2");
  ASSERT_FALSE(GatedExchange(server, client, ServoPacket16(1000, 1, 1500)).empty());  // silent
  server.Advance(10);
  EXPECT_EQ(TakeSilentRobots(&server), std::vector<int>{0});
  server.Advance(10);  // Not waited for again.
  EXPECT_TRUE(TakeSilentRobots(&server).empty());
  EXPECT_EQ(server.world().steps(0), 21);
  server.DropFromLockstep(0);  // on_silent_robot: SILENT_ROBOT_DROP
  EXPECT_EQ(server.world().rotor_target(0)[0], 0);
  client.Send(ServoPacket16(1000, 2, 1500));
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (server.counters(0).dropped_after_drop == 0 && MonotonicNowNs() < deadline) {
    if (WaitReadable(server.wait_fd(), 100)) server.Poll();
  }
  EXPECT_EQ(server.counters(0).dropped_after_drop, 1u);
  server.Advance(5);
  EXPECT_TRUE(client.Receive(0).empty());  // No reply while dropped.
  const std::string reply = GatedExchange(server, client, ServoPacket16(1000, 1, 1500));
  ASSERT_FALSE(reply.empty());
  EXPECT_EQ(server.counters(0).json_restarts, 1u);
  EXPECT_DOUBLE_EQ(Field(reply, "timestamp")[0], 0.027);  // 26 steps, then its first frame
  EXPECT_NEAR(Field(reply, "position")[1], 1, 1e-9);      // back at its start (NED east)
  EXPECT_GT(server.world().rotor_target(0)[0], 0);
  server.Advance(10);  // In the lock-step again: its next frame is waited for.
  EXPECT_EQ(TakeSilentRobots(&server), std::vector<int>{0});
}

// Two silent autopilots, one after the other: each is reported once, the first not again when
// the second times out.
TEST(ArduPilotJsonGateTest, EachSilentAutopilotIsReportedOnlyOnce) {
  const std::string port = std::to_string(TestJsonPort());
  const Scenario scenario = MakeScenario(
      "robot { name: \"a\" position_m { z: 10 } ardupilot_json_port: " + port +
      " }\nrobot { name: \"b\" position_m { x: 5 z: 10 } ardupilot_json_port: " + port + " }");
  PhysicsServer server(scenario, FrameGate(50 * kNsPerMs));
  JsonClient a("127.77.0.2");
  JsonClient b("127.77.0.6", "127.77.0.5");
  ASSERT_FALSE(GatedExchange(server, a, ServoPacket16(1000, 1, 1500)).empty());
  b.Send(ServoPacket16(1000, 1, 1500));
  for (int tries = 0; server.counters(1).json_frames == 0 && tries < 50; ++tries) {
    if (WaitReadable(server.wait_fd(), 100)) server.Poll();
  }
  ASSERT_EQ(server.counters(1).json_frames, 1u);
  // a is silent; b answers each reply until it falls silent too.
  std::thread b_answers([&] {
    for (uint32_t frame = 2; frame <= 20; ++frame) {
      if (b.Receive(5000).empty()) return;
      b.Send(ServoPacket16(1000, frame, 1500));
    }
  });
  server.Advance(10);
  EXPECT_EQ(TakeSilentRobots(&server), std::vector<int>{0});
  server.Advance(30);  // b answers 19 frames, then misses the gate.
  b_answers.join();
  EXPECT_EQ(TakeSilentRobots(&server), std::vector<int>{1});
}

// Realtime pacing: the clock follows the wall clock and never waits; a reply leaves when the
// clock reaches its frame's end, so no reply arrives before its time on the wall clock.
TEST(ArduPilotJsonGateTest, InRealtimeNoReplyArrivesBeforeItsTime) {
  const Scenario scenario =
      MakeScenario("robot { name: \"a\" position_m { z: 10 } ardupilot_json_port: " +
                   std::to_string(TestJsonPort()) + " }");
  PhysicsServer server(scenario);
  JsonClient client("127.77.0.2");
  const UniqueFd stop(eventfd(0, EFD_CLOEXEC));  // Written when the autopilot is done.
  std::vector<std::pair<TimeNs, double>> received;  // (wall ns since start, timestamp s)
  const TimeNs start_ns = MonotonicNowNs();
  std::thread ardupilot([&] {
    client.Send(ServoPacket16(200, 1, 1500));
    for (uint32_t frame = 2; frame <= 60; ++frame) {
      const std::string reply = client.Receive(2000);
      if (reply.empty()) break;
      received.emplace_back(MonotonicNowNs() - start_ns, Field(reply, "timestamp")[0]);
      client.Send(ServoPacket16(200, frame, 1500));
    }
    const uint64_t one = 1;
    [[maybe_unused]] ssize_t written = write(stop.get(), &one, sizeof one);
  });
  RunRealtime(&server, 1.0, 2 * kNsPerS, stop.get());
  ardupilot.join();
  ASSERT_GE(received.size(), 50u);
  double last_s = 0;
  for (const auto& [wall_ns, timestamp_s] : received) {
    // RunRealtime's clock starts after start_ns: virtual time t is never before wall t.
    EXPECT_GE(static_cast<double>(wall_ns) / kNsPerS, timestamp_s) << timestamp_s;
    EXPECT_GT(timestamp_s, last_s);
    last_s = timestamp_s;
  }
}

TEST(ArduPilotJsonCodecTest, PwmMapsLinearlyToRotorSpeed) {
  ServoPacket packet;
  packet.channels = 16;
  packet.pwm_us = {1000, 1500, 2000, 2200};
  const RotorSpeeds speeds = PwmToRotorSpeeds(packet, 2000);
  EXPECT_EQ(speeds[0], 0);
  EXPECT_EQ(speeds[1], 1000);
  EXPECT_EQ(speeds[2], 2000);
  EXPECT_EQ(speeds[3], 2000);  // clamped
}

}  // namespace
}  // namespace sitlnet::physics
