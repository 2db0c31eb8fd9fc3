// RemoteMedium + MediumLinkSimulator over a socket pair, without privileges:
// the medium behind the link produces, call for call, what the same medium
// produces in-process (the property that makes remote runs byte-identical;
// tests/integration/remote_run_test.cc checks it end to end).
#include <gtest/gtest.h>

#include <thread>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"

namespace sitlnet::network_side {
namespace {

// These tests drive the coordinator directly.
using namespace coordinator;  // NOLINT(google-build-using-namespace)

using coordinator::Channel;

Scenario ThreeRobots(uint64_t seed = 7) {
  return LoadScenarioText(
      "name: \"rmt\"\n"
      "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
      "robot { name: \"b\" position_m { x: 20 y: 0 z: 1 } }\n"
      "robot { name: \"c\" position_m { x: 0 y: 60 z: 1 } }\n"
      "timing { iteration_us: 10000 physics_step_us: 1000 network_step_us: 2000 pacing: "
      "PACING_LOCKSTEP seed: " +
          std::to_string(seed) + " }\n",
      "remote_medium_test");
}

// An Ethernet frame from `robot` to `destination` (broadcast or a robot).
std::vector<uint8_t> Frame(const Scenario& s, int robot, const MacAddress& destination, int bytes,
                           int tag) {
  std::vector<uint8_t> frame(14 + bytes, static_cast<uint8_t>(tag));
  std::copy(destination.bytes.begin(), destination.bytes.end(), frame.begin());
  const MacAddress& source = s.robots[robot].wlan_mac;
  std::copy(source.bytes.begin(), source.bytes.end(), frame.begin() + 6);
  frame[12] = 0x08;
  frame[13] = 0x00;
  return frame;
}

struct Output {
  std::vector<std::string> deliveries;  // Every field, as text.
  std::string pcap;                     // Every on-air frame, encoded.
};

// The calls a lockstep bridge makes: per δ_net step, positions, then each
// frame after advancing to its instant, then the step's end (tapbridge
// BridgeCore::StepLockstep). Robots a and b exchange unicast and broadcast
// frames; c moves into range half way.
Output Drive(tapbridge::MediumModel& medium, const Scenario& s) {
  Output out;
  std::vector<mac::Delivery> deliveries;
  std::vector<tapbridge::AirFrame> air;
  const auto collect = [&] {
    for (const mac::Delivery& d : deliveries) {
      out.deliveries.push_back(std::to_string(d.station) + "," + std::to_string(d.delivery_ns) +
                               "," + std::to_string(d.rx_power_dbm) + "," +
                               std::to_string(d.sinr_db) + "," +
                               std::string(d.ethernet_frame.begin(), d.ethernet_frame.end()));
    }
    for (const tapbridge::AirFrame& frame : air) out.pcap += tapbridge::EncodePcapRecord(frame, 0);
    deliveries.clear();
    air.clear();
  };
  const MacAddress broadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
  const TimeNs step = s.network_step_ns;
  for (int k = 0; k < 100; ++k) {
    const TimeNs from = k * step;
    medium.SetPosition(0, 0.1 * k, 0, 1);
    medium.SetPosition(2, 0, k < 25 ? 60 : 5, 1);
    // Steps 50-99 are quiet except every 10th: the remote link may skip them.
    for (int f = 0; f < (k < 50 || k % 10 == 0 ? 3 : 0); ++f) {
      const TimeNs at = from + (f * 613 + k * 97) % step;
      medium.AdvanceTo(at, &deliveries, &air);
      collect();
      const int robot = (k + f) % 3;
      medium.Submit(robot, at,
                    Frame(s, robot, f == 1 ? s.robots[(robot + 1) % 3].wlan_mac : broadcast,
                          200 + 50 * f, k));
    }
    medium.AdvanceTo(from + step, &deliveries, &air);
    collect();
  }
  return out;
}

TEST(RemoteMedium, ProducesCallForCallWhatTheMediumProducesInProcess) {
  const Scenario scenario = ThreeRobots();
  auto local = tapbridge::MakeMacPhySimMedium(scenario);
  const Output expected = Drive(*local, scenario);
  ASSERT_GT(expected.deliveries.size(), 100u);   // Traffic crossed, c joined half way.
  ASSERT_GT(expected.pcap.size(), 150u * 100u);  // Data frames and ACKs on the air.

  auto [coordinator_end, connector_end] = coordinator::SocketPair();
  std::string reason;
  std::thread server([&, fd = std::move(connector_end)]() mutable {
    Channel channel(std::move(fd));
    MediumLinkSimulator simulator(scenario, tapbridge::MakeMacPhySimMedium(scenario));
    reason = coordinator::ServeCoordinator(
        channel, simulator,
        {"medium@test", coordinator::Role::kNetwork, MediumScenarioHash(scenario)}, 5 * kNsPerS);
  });
  coordinator::HandshakeExpectation expect;
  expect.scenario_hash = MediumScenarioHash(scenario);
  expect.iteration_ns = scenario.iteration_ns;
  expect.role = coordinator::Role::kNetwork;
  coordinator::WaitLimits limits{MonotonicNowNs() + 5 * kNsPerS, 5 * kNsPerS, -1};
  RemoteMedium remote(
      scenario, coordinator::AcceptConnector(Channel(std::move(coordinator_end)), expect, limits),
      5 * kNsPerS);
  const Output got = Drive(remote, scenario);
  EXPECT_EQ(got.deliveries, expected.deliveries);
  EXPECT_EQ(got.pcap, expected.pcap);
  // At most one round trip per δ_net step, whatever the number of frames;
  // none for a step without frames once the medium has gone quiet.
  EXPECT_EQ(remote.stats().round_trips + remote.stats().quiet_steps, 100);
  EXPECT_GT(remote.stats().quiet_steps, 20);
  const int64_t round_trips = remote.stats().round_trips;
  for (int i = 0; i < 3; ++i) {
    const tapbridge::MediumCounters want = local->Counters(i);
    const tapbridge::MediumCounters have = remote.Counters(i);
    EXPECT_EQ(have.sent, want.sent) << i;
    EXPECT_EQ(have.delivered, want.delivered) << i;
    EXPECT_EQ(have.lost, want.lost) << i;
    EXPECT_EQ(have.other, want.other) << i;
  }
  EXPECT_EQ(remote.stats().round_trips, round_trips + 1);  // The counters: one more.
  remote.Stop("done");
  server.join();
  EXPECT_EQ(reason, "done");
}

TEST(RemoteMedium, ScenarioHashIgnoresDurationAndPacingButNotTheSeed) {
  const Scenario base = ThreeRobots(7);
  Scenario longer = base;
  longer.spec.mutable_timing()->set_duration_ms(123456);
  longer.spec.mutable_timing()->set_pacing(proto::Timing::PACING_REALTIME);
  EXPECT_EQ(MediumScenarioHash(base), MediumScenarioHash(longer));
  EXPECT_NE(MediumScenarioHash(base), MediumScenarioHash(ThreeRobots(8)));
}

// A frame crosses the link once, whoever needs it: its deliveries and its on-air record (for the
// pcap) name the same entry of the reply's frames. Oracle: one 1500-byte unicast frame, answered
// by an ACK; the reply is the frame plus small fixed-size records, not two copies of it.
TEST(MediumLinkSimulator, SendsEachFrameOnceForItsDeliveriesAndItsAirRecord) {
  const Scenario scenario = ThreeRobots();
  MediumLinkSimulator simulator(scenario, tapbridge::MakeMacPhySimMedium(scenario));
  struct NoContext : coordinator::IterationContext {
    void CommandsCollected() override {}
  } context;
  const std::vector<uint8_t> frame = Frame(scenario, 0, scenario.robots[1].wlan_mac, 1500, 9);
  proto::medium::MediumRequest request;
  proto::medium::SubmitOp* submit = request.add_ops()->mutable_submit();
  submit->set_station(0);
  submit->set_ethernet(frame.data(), frame.size());
  proto::medium::AdvanceOp* advance = request.add_ops()->mutable_advance();
  advance->set_until_ns(5 * kNsPerMs);
  advance->set_trace_air(true);
  proto::coord::Start start;
  proto::coord::End end;
  start.set_payload(request.SerializeAsString());
  simulator.RunIteration(start, &end, context);
  proto::medium::MediumReply reply;
  ASSERT_TRUE(reply.ParseFromString(end.payload()));
  ASSERT_EQ(reply.deliveries_size(), 1);  // Unicast: b only.
  ASSERT_EQ(reply.air_size(), 2);         // DATA, ACK.
  ASSERT_EQ(reply.frames_size(), 1);
  EXPECT_EQ(reply.frames(0), std::string(frame.begin(), frame.end()));
  EXPECT_EQ(reply.deliveries(0).frame_index(), 0);
  EXPECT_EQ(reply.air(0).frame_index(), 0);
  EXPECT_EQ(reply.air(1).frame_index(), -1);
  EXPECT_LT(end.payload().size(), frame.size() + 300);
}

TEST(MediumLinkSimulator, RefusesMalformedRequestsWithOneLine) {
  const Scenario scenario = ThreeRobots();
  MediumLinkSimulator simulator(scenario, tapbridge::MakeMacPhySimMedium(scenario));
  struct NoContext : coordinator::IterationContext {
    void CommandsCollected() override {}
  } context;
  proto::coord::Start start;
  proto::coord::End end;
  start.set_iteration(4);
  start.set_payload("\xff\xff\xff garbage");
  try {
    simulator.RunIteration(start, &end, context);
    FAIL() << "accepted garbage";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("medium request 4 is not a MediumRequest"),
              std::string::npos)
        << e.what();
  }
  proto::medium::MediumRequest request;
  request.add_ops()->mutable_position()->set_station(3);
  start.set_payload(request.SerializeAsString());
  try {
    simulator.RunIteration(start, &end, context);
    FAIL() << "accepted station 3";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("station 3 out of range (the scenario has 3 robots)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace sitlnet::network_side
