// Who hears whom: distance (line3) and obstacle shadowing with a position
// update through the daemon's control socket.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "tests/integration/tapbridge_test_util.h"

namespace sitlnet::tapbridge::testing {
namespace {

bool Pings(MediumScenario& s, const std::string& from, int to) {
  return s.Exec(from, {PingProgram(), "-c", "2", "-W", "1", "-i", "0.2", s.Address(to)})
             .exit_code == 0;
}

// scenarios/line3.textproto as written, under a test-local name and subnets.
TEST(TapbridgeTopology, Line3EndsHearTheMiddleNotEachOther) {
  SITLNET_REQUIRE_ROOT();
  std::ifstream file(SourceDir() + "/scenarios/line3.textproto");
  ASSERT_TRUE(file) << "scenarios/line3.textproto";
  std::string body, line;
  while (std::getline(file, line)) {
    if (line.rfind("name:", 0) != 0) body += line + "\n";
  }
  MediumScenario scenario("l3", 0, body);
  scenario.StartDaemon();
  EXPECT_TRUE(Pings(scenario, "r1", 1));
  EXPECT_TRUE(Pings(scenario, "r3", 1));
  EXPECT_FALSE(Pings(scenario, "r1", 2));
  EXPECT_FALSE(Pings(scenario, "r3", 0));
}

// 802.11a at 6 Mb/s; a (0,0,1) and b (30,0,1) with a 2 m thick, 10 m high
// wall at x = 15: 30 m costs 46.73 + 30 log10(30) = 91.0 dB (-75 dBm, 19 dB
// SNR: a clean link at 6 Mb/s); the wall adds 2 x 9 + 0.4 x 2 = 18.8 dB
// (Sommer et al.), -94 dBm, under the -82 dBm preamble threshold: no link.
// Moving b to (0,30,1) restores line of sight at the same distance.
TEST(TapbridgeTopology, WallCutsLinkAndPositionUpdateRestoresIt) {
  SITLNET_REQUIRE_ROOT();
  MediumScenario scenario("obs", 1,
                          "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
                          "robot { name: \"b\" position_m { x: 30 y: 0 z: 1 } }\n"
                          "obstacle { name: \"wall\" center_m { x: 15 y: 0 z: 5 }"
                          " size_m { x: 2 y: 100 z: 10 } }\n"
                          "radio { standard: STANDARD_80211A rate_mbps: 6 }\n");
  scenario.StartDaemon();
  EXPECT_FALSE(Pings(scenario, "a", 1));
  scenario.SetPosition("b", 0, 30, 1);
  EXPECT_TRUE(Pings(scenario, "a", 1));
  scenario.SetPosition("b", 30, 0, 1);
  EXPECT_FALSE(Pings(scenario, "a", 1));
}

}  // namespace
}  // namespace sitlnet::tapbridge::testing
