// Relay medium semantics (the benchmark's floor) without TAPs.
#include <gtest/gtest.h>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

std::vector<uint8_t> Frame(const MacAddress& dst, const MacAddress& src) {
  std::vector<uint8_t> f(dst.bytes.begin(), dst.bytes.end());
  f.insert(f.end(), src.bytes.begin(), src.bytes.end());
  f.insert(f.end(), {0x08, 0x00, 1, 2, 3});
  return f;
}

TEST(RelayMedium, UnicastToOwnerGroupToAllOthers) {
  const std::vector<MacAddress> macs = {RobotMac(0), RobotMac(1), RobotMac(2)};
  auto medium = MakeRelayMedium(macs);
  std::vector<Delivery> out;
  medium->Submit(0, 100, Frame(RobotMac(2), RobotMac(0)));
  EXPECT_EQ(medium->NextEventNs(), 100);
  medium->AdvanceTo(100, &out, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0].station, 2);
  EXPECT_EQ(out[0].delivery_ns, 100);
  EXPECT_EQ(out[0].source, 0);
  out.clear();
  MacAddress broadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
  medium->Submit(1, 200, Frame(broadcast, RobotMac(1)));
  medium->AdvanceTo(200, &out, nullptr);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].station, 0);
  EXPECT_EQ(out[1].station, 2);
  medium->SetStationEnabled(2, false);
  out.clear();
  medium->Submit(1, 300, Frame(broadcast, RobotMac(1)));
  medium->AdvanceTo(300, &out, nullptr);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(medium->NextEventNs().has_value());
}

}  // namespace
}  // namespace sitlnet::tapbridge

namespace sitlnet::tapbridge {
namespace {

// A caller may destroy its EventLoop before the BridgeCore registered on it
// (declaration order); the core must not touch the dead loop.
TEST(BridgeCore, LoopMayDieBeforeTheCore) {
  const Scenario scenario = LoadScenarioText("name: \"u\" robot { name: \"a\" }", "<test>");
  BridgeCore core(scenario, MakeRelayMedium({RobotMac(0)}), BridgeOptions{});
  {
    EventLoop loop;
    clock::Timebase timebase;
    timebase.Begin(MonotonicNowNs());
    core.StartRealtime(&loop, timebase);
    loop.RunOnce(0);
  }
  EXPECT_GE(core.VirtualNowNs(), 0);
}

TEST(BridgeCore, StopRealtimeThenLoopRunsWithoutTheCore) {
  const Scenario scenario = LoadScenarioText("name: \"u\" robot { name: \"a\" }", "<test>");
  EventLoop loop;
  {
    BridgeCore core(scenario, MakeRelayMedium({RobotMac(0)}), BridgeOptions{});
    clock::Timebase timebase;
    timebase.Begin(MonotonicNowNs());
    core.StartRealtime(&loop, timebase);
  }
  loop.RunOnce(0);  // The after-batch hook was removed with the core.
}

}  // namespace
}  // namespace sitlnet::tapbridge
