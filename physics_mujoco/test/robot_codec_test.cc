// Native protocol over UDP on loopback (127.77.0.0/16 stands in for the ctl0 /30s).
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cmath>
#include <limits>

#include "physics_mujoco/client/physics_client.h"
#include "physics_mujoco/physics_mujoco.h"
#include "physics_mujoco/test/test_scenarios.h"

namespace sitlnet::physics {
namespace {

using physics_client::PhysicsClient;
using testing::MakeScenario;
using testing::TestPhysicsPort;
using testing::WaitReadable;

// Robot 0: server 127.77.0.1, robot side 127.77.0.2; robot 1: .5 / .6.
const char kTwoRobots[] =
    "robot { name: \"a\" position_m { z: 5 } }\n"
    "robot { name: \"b\" position_m { x: 3 z: 5 } }";

std::string ServerOf(int robot) {
  return "127.77.0." + std::to_string(4 * robot + 1) + ":" + std::to_string(TestPhysicsPort());
}
std::string RobotSideOf(int robot) { return "127.77.0." + std::to_string(4 * robot + 2); }

uint64_t Dropped(const RobotCounters& c) {
  return c.dropped_malformed + c.dropped_invalid + c.dropped_wrong_robot + c.dropped_foreign_source;
}

// Handles packets until `done` holds or 5 s pass (event-driven: waits on the server's fd).
template <typename Done>
void PollUntil(PhysicsServer* server, Done done) {
  const TimeNs deadline = MonotonicNowNs() + 5 * kNsPerS;
  while (!done() && MonotonicNowNs() < deadline) {
    if (WaitReadable(server->wait_fd(), 100)) server->Poll();
  }
}

class ControlServerTest : public ::testing::Test {
 protected:
  ControlServerTest() : scenario_(MakeScenario(kTwoRobots)), server_(scenario_) {}
  Scenario scenario_;
  PhysicsServer server_;
};

TEST_F(ControlServerTest, CommandInStateOut) {
  PhysicsClient client(ServerOf(0), RobotSideOf(0));
  client.set_robot_index(0);
  ASSERT_TRUE(client.SendRotorSpeeds({500, 600, 700, 800}, 42));
  PollUntil(&server_, [&] { return server_.counters(0).commands_accepted == 1; });
  ASSERT_EQ(server_.counters(0).commands_accepted, 1u);
  EXPECT_EQ(server_.world().rotor_target(0)[3], 800);
  // 100 Hz state rate, 1 ms steps: one state after 10 steps.
  server_.Advance(10);
  proto::RobotState state;
  ASSERT_TRUE(client.Receive(&state, 2000));
  EXPECT_EQ(state.robot(), 0u);
  EXPECT_EQ(state.step(), 10u);
  EXPECT_EQ(state.sim_time_ns(), 10 * kNsPerMs);
  EXPECT_EQ(state.command_step(), 42u);
  EXPECT_FALSE(state.motors_cut());
  EXPECT_EQ(state.position_m().z(), server_.world().Pose(0).position_m.z);
  EXPECT_EQ(state.orientation().w(), server_.world().Pose(0).orientation.w);
  ASSERT_EQ(state.rotor_speed_rad_s_size(), 4);
  EXPECT_GT(state.rotor_speed_rad_s(3), 0);
  EXPECT_EQ(server_.counters(0).states_sent, 1u);
  // Robot 1 never spoke: no state for it, nothing counted against it.
  EXPECT_EQ(server_.counters(1).states_sent, 0u);
}

TEST_F(ControlServerTest, ThrottlesScaleToMaxSpeed) {
  PhysicsClient client(ServerOf(1), RobotSideOf(1));
  ASSERT_TRUE(client.SendThrottles({0, 0.5, 1, 0.25}));
  PollUntil(&server_, [&] { return server_.counters(1).commands_accepted == 1; });
  const double max = server_.world().airframe(1).max_rotor_speed_rad_s();
  EXPECT_EQ(server_.world().rotor_target(1)[1], 0.5 * max);
  EXPECT_EQ(server_.world().rotor_target(1)[2], max);
}

TEST_F(ControlServerTest, CommandsHoldUntilReplacedThenTheFailsafeCutsMotors) {
  PhysicsClient client(ServerOf(0), RobotSideOf(0));
  ASSERT_TRUE(client.SendRotorSpeeds({1000, 1000, 1000, 1000}));
  PollUntil(&server_, [&] { return server_.counters(0).commands_accepted == 1; });
  server_.Advance(499);  // default command_timeout_ms 500
  EXPECT_EQ(server_.world().rotor_target(0)[0], 1000);
  EXPECT_EQ(server_.counters(0).failsafe_cuts, 0u);
  server_.Advance(1);
  EXPECT_EQ(server_.world().rotor_target(0)[0], 0);
  EXPECT_EQ(server_.counters(0).failsafe_cuts, 1u);
  server_.Advance(10);
  proto::RobotState state;
  ASSERT_TRUE(client.ReceiveLatest(&state, 2000));
  EXPECT_TRUE(state.motors_cut());
  // A new command lifts the cut.
  ASSERT_TRUE(client.SendRotorSpeeds({900, 900, 900, 900}));
  PollUntil(&server_, [&] { return server_.counters(0).commands_accepted == 2; });
  EXPECT_EQ(server_.world().rotor_target(0)[0], 900);
  server_.Advance(10);
  ASSERT_TRUE(client.ReceiveLatest(&state, 2000));
  EXPECT_FALSE(state.motors_cut());
  EXPECT_EQ(server_.counters(0).failsafe_cuts, 1u);
}

// Sends raw bytes from `from` (robot-side address) to robot `robot`'s server socket.
void SendRaw(const std::string& from, int robot, const std::string& bytes) {
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  inet_pton(AF_INET, from.c_str(), &local.sin_addr);
  ASSERT_EQ(bind(fd, reinterpret_cast<sockaddr*>(&local), sizeof local), 0);
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(TestPhysicsPort());
  const std::string host = "127.77.0." + std::to_string(4 * robot + 1);
  inet_pton(AF_INET, host.c_str(), &to.sin_addr);
  ASSERT_EQ(sendto(fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to),
            static_cast<ssize_t>(bytes.size()));
  close(fd);
}

std::string Command(std::initializer_list<double> speeds, std::optional<uint32_t> robot = {}) {
  proto::MotorCommand command;
  if (robot) command.set_robot(*robot);
  for (double s : speeds) command.add_rotor_speed_rad_s(s);
  return command.SerializeAsString();
}

TEST_F(ControlServerTest, BadPacketsAreDroppedAndCountedAndTheServerKeepsRunning) {
  const double max = server_.world().airframe(0).max_rotor_speed_rad_s();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::string good = Command({100, 100, 100, 100});
  const std::string me = RobotSideOf(0);
  SendRaw(me, 0, good.substr(0, good.size() - 3));       // truncated
  SendRaw(me, 0, std::string(12, '\xff'));               // garbage
  SendRaw(me, 0, std::string(3000, '\x08'));             // oversize
  SendRaw(me, 0, Command({100, nan, 100, 100}));         // NaN
  SendRaw(me, 0, Command({100, 100, max * 1.01, 100}));  // above max
  SendRaw(me, 0, Command({100, -1, 100, 100}));          // negative
  SendRaw(me, 0, Command({100, 100, 100}));              // 3 rotors
  SendRaw(me, 0, Command({}, 0));                        // no values
  SendRaw(me, 0, Command({100, 100, 100, 100}, 1));      // robot 1's index
  SendRaw(RobotSideOf(1), 0, good);                      // robot 1 driving robot 0
  SendRaw("127.0.0.1", 0, good);                         // foreign host
  PollUntil(&server_, [&] { return Dropped(server_.counters(0)) == 11; });
  const RobotCounters& c = server_.counters(0);
  EXPECT_EQ(c.dropped_malformed, 3u);
  EXPECT_EQ(c.dropped_invalid, 5u);
  EXPECT_EQ(c.dropped_wrong_robot, 1u);
  EXPECT_EQ(c.dropped_foreign_source, 2u);
  EXPECT_EQ(c.commands_accepted, 0u);
  EXPECT_EQ(server_.world().rotor_target(0)[0], 0);
  EXPECT_EQ(server_.world().rotor_target(1)[0], 0);
  // Still serving: a good command is accepted and answered.
  PhysicsClient client(ServerOf(0), me);
  ASSERT_TRUE(client.SendRotorSpeeds({100, 100, 100, 100}));
  PollUntil(&server_, [&] { return server_.counters(0).commands_accepted == 1; });
  server_.Advance(10);
  proto::RobotState state;
  EXPECT_TRUE(client.Receive(&state, 2000));
  EXPECT_EQ(Dropped(server_.counters(0)), 11u);
}

TEST_F(ControlServerTest, LockStepSendsStatesAndCollectsTheCommandsForThem) {
  PhysicsClient a(ServerOf(0), RobotSideOf(0));
  PhysicsClient b(ServerOf(1), RobotSideOf(1));
  ASSERT_TRUE(a.SendRotorSpeeds({100, 100, 100, 100}));
  ASSERT_TRUE(b.SendRotorSpeeds({100, 100, 100, 100}));
  PollUntil(&server_, [&] { return server_.counters(1).commands_accepted == 1; });
  server_.Advance(3);  // not a state period: no periodic state
  server_.SendStates();
  proto::RobotState state;
  ASSERT_TRUE(a.Receive(&state, 2000));
  EXPECT_EQ(state.step(), 3u);
  ASSERT_TRUE(a.SendRotorSpeeds({200, 200, 200, 200}, state.step()));
  // Robot b got its state too but does not answer: it is reported missing after the timeout.
  ASSERT_TRUE(b.Receive(&state, 2000));
  EXPECT_EQ(server_.CollectCommands(50 * kNsPerMs), std::vector<int>{1});
  EXPECT_EQ(server_.world().rotor_target(0)[0], 200);
  ASSERT_TRUE(b.SendRotorSpeeds({300, 300, 300, 300}, state.step()));
  EXPECT_TRUE(server_.CollectCommands(5 * kNsPerS).empty());
  EXPECT_EQ(server_.world().rotor_target(1)[0], 300);
}

TEST_F(ControlServerTest, RealtimeModeRunsForItsDurationAndServesCommands) {
  PhysicsClient client(ServerOf(0), RobotSideOf(0));
  ASSERT_TRUE(client.SendRotorSpeeds({700, 700, 700, 700}));
  // 200 ms of virtual time at 20 x real time.
  RunRealtime(&server_, 20.0, 200 * kNsPerMs, -1);
  EXPECT_EQ(server_.world().time_ns(0), 200 * kNsPerMs);
  EXPECT_EQ(server_.counters(0).commands_accepted, 1u);
  EXPECT_EQ(server_.counters(0).states_sent, 20u);  // 100 Hz
  proto::RobotState state;
  ASSERT_TRUE(client.ReceiveLatest(&state, 2000));
  EXPECT_EQ(state.sim_time_ns(), 200 * kNsPerMs);
}

// A bad state rate never reaches the server: loading the scenario refuses it in one line naming
// the file, the robot and the field.
TEST(ControlServerConfigTest, BadStateRateIsAOneLineErrorNamingTheRobot) {
  try {
    MakeScenario("robot { name: \"a\" state_rate_hz: 0 }");
    FAIL() << "accepted state_rate_hz 0";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_NE(message.find("test.textproto:"), std::string::npos) << message;
    EXPECT_NE(message.find("robot \"a\": state_rate_hz 0 out of range"), std::string::npos)
        << message;
  }
}

}  // namespace
}  // namespace sitlnet::physics
