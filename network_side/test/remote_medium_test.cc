// RemoteMedium + MediumLinkSimulator over a socket pair, without privileges:
// the medium behind the link produces, call for call, what the same medium
// produces in-process (the property that makes remote runs byte-identical;
// tests/integration/remote_run_test.cc checks it end to end).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <thread>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"

namespace sitlnet::network_side {
namespace {

// These tests drive the coordinator directly.
using namespace coordinator;  // NOLINT(google-build-using-namespace)

using coordinator::Channel;

Scenario ThreeRobots(uint64_t seed = 7, const std::string& radio = "") {
  return LoadScenarioText(
      "name: \"rmt\"\n" + radio +
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

// Drives the in-process medium and a RemoteMedium over a socket pair with the same calls and
// expects the same deliveries, pcap records and counters.
struct RemoteRun {
  std::string pcap;
  int64_t quiet_steps = 0;  // Steps the remote side skipped its round trip.
};
RemoteRun ExpectRemoteMatchesLocal(const Scenario& scenario) {
  auto local = tapbridge::MakeMacPhySimMedium(scenario);
  const Output expected = Drive(*local, scenario);
  EXPECT_GT(expected.deliveries.size(), 100u);   // Traffic crossed, c joined half way.
  EXPECT_GT(expected.pcap.size(), 150u * 100u);  // Data frames and ACKs on the air.

  auto [coordinator_end, connector_end] = coordinator::SocketPair();
  std::string reason;
  std::thread server([&, fd = std::move(connector_end)]() mutable {
    Channel channel(std::move(fd));
    MediumLinkSimulator simulator(scenario, tapbridge::MakeMacPhySimMedium(scenario));
    reason = coordinator::ServeCoordinator(
        channel, simulator,
        {"medium@test", coordinator::Role::kNetwork, MediumScenarioHash(scenario), {}},
        5 * kNsPerS);
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
  const int64_t quiet_steps = remote.stats().quiet_steps;
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
  return {got.pcap, quiet_steps};
}

TEST(RemoteMedium, ProducesCallForCallWhatTheMediumProducesInProcess) {
  EXPECT_GT(ExpectRemoteMatchesLocal(ThreeRobots()).quiet_steps, 20);
}

// 802.11ac: the air frames keep their VHT mode across the link (the pcap's VHT field).
TEST(RemoteMedium, CarriesVhtModesOfAirFrames) {
  const std::string pcap =
      ExpectRemoteMatchesLocal(ThreeRobots(7, "radio { standard: STANDARD_80211AC mcs: 5 }\n")).pcap;
  // A record's radiotap it_present with the VHT bit (21): bytes 0x6b 0x08 0x20 0x00.
  EXPECT_NE(pcap.find(std::string("\x6b\x08\x20\x00", 4)), std::string::npos);
}

// A medium peer that answers every request with the reply `craft` makes (issue 17, finding 4:
// the peer's reply is input).
class HostileMedium final : public coordinator::Simulator {
 public:
  explicit HostileMedium(std::function<void(proto::medium::MediumReply*)> craft)
      : craft_(std::move(craft)) {}
  void RunIteration(const proto::coord::Start&, proto::coord::End* end,
                    coordinator::IterationContext&) override {
    proto::medium::MediumReply reply;
    craft_(&reply);
    reply.SerializeToString(end->mutable_payload());
  }

 private:
  std::function<void(proto::medium::MediumReply*)> craft_;
};

// Submits one 100-byte broadcast from robot a at 1 ms and advances to the step's end (2 ms)
// through a RemoteMedium whose peer is `craft`'s; returns the Error's text ("" if none).
std::string AttackWith(std::function<void(proto::medium::MediumReply*)> craft) {
  const Scenario scenario = ThreeRobots();
  auto [coordinator_end, connector_end] = coordinator::SocketPair();
  std::thread server([&, fd = std::move(connector_end)]() mutable {
    Channel channel(std::move(fd));
    HostileMedium hostile(craft);
    try {
      coordinator::ServeCoordinator(
          channel, hostile,
          {"hostile", coordinator::Role::kNetwork, MediumScenarioHash(scenario), {}}, 5 * kNsPerS);
    } catch (const Error&) {
    }
  });
  coordinator::HandshakeExpectation expect;
  expect.scenario_hash = MediumScenarioHash(scenario);
  expect.iteration_ns = scenario.iteration_ns;
  coordinator::WaitLimits limits{MonotonicNowNs() + 5 * kNsPerS, 5 * kNsPerS, -1};
  std::string error;
  {
    RemoteMedium remote(
        scenario, coordinator::AcceptConnector(Channel(std::move(coordinator_end)), expect, limits),
        5 * kNsPerS);
    const MacAddress broadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
    std::vector<mac::Delivery> deliveries;
    std::vector<tapbridge::AirFrame> air;
    remote.AdvanceTo(kNsPerMs, &deliveries, &air);
    remote.Submit(0, kNsPerMs, Frame(scenario, 0, broadcast, 100, 1));
    try {
      remote.AdvanceTo(2 * kNsPerMs, &deliveries, &air);
    } catch (const Error& e) {
      error = e.what();
    }
    if (error.empty()) {
      EXPECT_EQ(deliveries.size(), 2u);
    }
    remote.Stop("done");
  }
  server.join();
  return error;
}

TEST(RemoteMedium, RepliesAnHonestMediumCannotMakeEndTheLinkNamingWhy) {
  const std::vector<uint8_t> sent =
      Frame(ThreeRobots(), 0, MacAddress{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}}, 100, 1);
  const std::string frame(sent.begin(), sent.end());
  const auto deliver = [&](proto::medium::MediumReply* reply, int station, TimeNs at_ns) {
    proto::medium::Delivery* d = reply->add_deliveries();
    d->set_station(station);
    d->set_time_ns(at_ns);
    d->set_frame(frame);
    d->set_rx_power_dbm(-60);
    d->set_sinr_db(30);
    return d;
  };
  // What the broadcast can give: one copy to each of the two other robots, in the step.
  EXPECT_EQ(AttackWith([&](proto::medium::MediumReply* r) {
              deliver(r, 1, 1500 * kNsPerUs);
              deliver(r, 2, 1500 * kNsPerUs);
            }),
            "");
  const auto attack = [&](std::function<void(proto::medium::MediumReply*)> craft) {
    const std::string error = AttackWith(craft);
    EXPECT_EQ(error.rfind("network connector 'hostile': medium reply ", 0), 0u) << error;
    return error.substr(error.find("medium reply ") + 13);
  };
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) { deliver(r, 3, 1500 * kNsPerUs); }),
            "delivers to station 3 of 3");
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) { deliver(r, 1, 3 * kNsPerMs); }),
            "delivers at 3000000 ns, outside the step [0, 2000000] ns");
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) {
              deliver(r, 1, 1500 * kNsPerUs)->set_rx_power_dbm(std::nan(""));
            }),
            "delivers with a received power or SINR that is not a number");
  // A few bytes of reply asking for many copies of one frame (the copies used to be made).
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) {
              r->add_frames(frame);
              for (int i = 0; i < 1000; ++i) {
                proto::medium::Delivery* d = deliver(r, 1, 1500 * kNsPerUs);
                d->clear_frame();
                d->set_frame_index(0);
              }
            }),
            "delivers more frames than the robots sent could make (one per other station)");
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) {
              deliver(r, 1, 1500 * kNsPerUs)->set_frame(std::string(5000, 'x'));
            }),
            "delivers a frame of 5000 bytes, longer than any the robots sent (114)");
  // Air frames (pcap records): from a station that does not exist, and a reply of a few kB
  // naming one frame a thousand times.
  const auto air = [&](proto::medium::MediumReply* reply, int transmitter) {
    proto::medium::AirFrame* a = reply->add_air();
    a->set_start_ns(1 * kNsPerMs);
    a->set_duration_ns(200 * kNsPerUs);
    a->set_transmitter(transmitter);
    a->set_rate_mbps(6);
    a->set_signal_dbm(-60);
    a->set_noise_dbm(-95);
    a->set_frame_index(0);
  };
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) {
              r->add_frames(frame);
              air(r, 7);
            }),
            "has an air frame from station 7 of 3");
  EXPECT_EQ(attack([&](proto::medium::MediumReply* r) {
              r->add_frames(frame);
              for (int i = 0; i < 1000; ++i) air(r, 0);
            }),
            "has more air frames than the robots' frames could make (64 each)");
}

TEST(RemoteMedium, ScenarioHashIgnoresDurationPacingAndWaitForRobotsButNotTheSeed) {
  const Scenario base = ThreeRobots(7);
  Scenario longer = base;
  longer.spec.mutable_timing()->set_duration_ms(123456);
  longer.spec.mutable_timing()->set_pacing(proto::Timing::PACING_REALTIME);
  longer.spec.mutable_timing()->set_wait_for_robots(false);  // set, not left out
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
  // Times near int64's end would overflow inside the model (found by remote_medium_request_fuzz:
  // a submit at INT64_MAX, then DIFS added to it); before the bound they reached it.
  const std::string frame(60, '\x01');
  for (const TimeNs bad_ns : {std::numeric_limits<TimeNs>::max(), TimeNs{-1}}) {
    for (const bool submit : {true, false}) {
      request.Clear();
      if (submit) {
        request.add_ops()->mutable_submit()->set_at_ns(bad_ns);
        request.mutable_ops(0)->mutable_submit()->set_ethernet(frame);
      } else {
        request.add_ops()->mutable_advance()->set_until_ns(bad_ns);
      }
      start.set_payload(request.SerializeAsString());
      try {
        simulator.RunIteration(start, &end, context);
        FAIL() << "accepted a time of " << bad_ns << " ns";
      } catch (const Error& e) {
        const std::string expected = std::string(submit ? "submit at " : "advance until ") +
                                     std::to_string(bad_ns) + " ns outside [0, ";
        EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
      }
    }
  }
  // The bound itself (the longest scenario's end and a step) is served, in a fresh medium, and
  // the model's sums from it are right: the frame queued there would go on air DIFS later
  // (34 us in 802.11a, 10.3.2.3.7: SIFS 16 + 2 slots of 9).
  MediumLinkSimulator fresh(scenario, tapbridge::MakeMacPhySimMedium(scenario));
  const TimeNs last_ns = kMaxDurationMs * kNsPerMs + scenario.iteration_ns;
  request.Clear();
  request.add_ops()->mutable_submit()->set_at_ns(last_ns);
  request.mutable_ops(0)->mutable_submit()->set_ethernet(frame);
  request.add_ops()->mutable_advance()->set_until_ns(last_ns);
  start.set_payload(request.SerializeAsString());
  ASSERT_NO_THROW(fresh.RunIteration(start, &end, context));
  proto::medium::MediumReply reply;
  ASSERT_TRUE(reply.ParseFromString(end.payload()));
  EXPECT_EQ(reply.next_event_ns(), last_ns + 34 * kNsPerUs);
  request.mutable_ops(1)->mutable_advance()->set_until_ns(last_ns + 1);
  start.set_payload(request.SerializeAsString());
  EXPECT_THROW(fresh.RunIteration(start, &end, context), Error);
}

}  // namespace
}  // namespace sitlnet::network_side
