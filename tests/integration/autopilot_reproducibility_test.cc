// Two lockstep runs of the real ArduCopter SITL (issue 31, item 6) give the same flight: a ground
// station on the simulated radio arms it, and it takes off. The station is a robot of the
// scenario that takes part in the lock-step (tests/node_mavlink/guided_flight_lockstep.cjs), so
// its commands enter the medium at the same virtual instants in every run.
// docs/autopilots-evidence.md, "Reproducibility", has the measurements and the reasons.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "tests/integration/run_test_util.h"
#include "verify/verify.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::ReadAll;
using integration_test::TempDir;
// medium.pcap with the fields the robots' kernels draw at random, and ArduCopter's logger health
// bit, masked (`sitlnet verify` masks the same).
using verify::WithoutHostDecidedFields;

// Where two captures first differ: the frame's number and time, the offset in it, and its bytes
// in each, so a failure says which field the masks missed.
std::string FirstDifference(const std::string& a, const std::string& b) {
  size_t at = 24;
  for (size_t frame_number = 1; at + 16 <= a.size() && at + 16 <= b.size(); ++frame_number) {
    const uint32_t length = static_cast<uint8_t>(a[at + 8]) | static_cast<uint8_t>(a[at + 9]) << 8 |
                            static_cast<uint8_t>(a[at + 10]) << 16 |
                            static_cast<uint32_t>(static_cast<uint8_t>(a[at + 11])) << 24;
    const size_t end = std::min(at + 16 + length, std::min(a.size(), b.size()));
    if (a.compare(at, end - at, b, at, end - at) != 0) {
      size_t offset = at;
      while (a[offset] == b[offset]) ++offset;
      const auto hex = [&](const std::string& capture) {
        std::string text;
        char byte[4];
        for (size_t i = at; i < std::min(at + 16 + length, capture.size()); ++i) {
          std::snprintf(byte, sizeof byte, "%02x", static_cast<uint8_t>(capture[i]));
          text += byte;
        }
        return text;
      };
      return "frame " + std::to_string(frame_number) + " (record at byte " + std::to_string(at) +
             ") differs at its byte " + std::to_string(offset - at) + " (16 = record header)\n  first:  " +
             hex(a) + "\n  second: " + hex(b);
    }
    at += 16 + length;
  }
  return a.size() == b.size() ? "no difference" : "one capture is longer: " +
                                                      std::to_string(a.size()) + " and " +
                                                      std::to_string(b.size()) + " bytes";
}

// 50 virtual seconds: ArduCopter's EKF uses GPS at about 41 s (arducopter_flight_test.cc), it
// arms then and climbs towards 10 m for the rest of the run. Oracle: two runs of the same
// inputs; what each compares is what the lock-step orders (docs/coordinator.md).
TEST(ArduCopterReproducibilityTest, TwoLockstepFlightsAreTheSameByteForByte) {
  SITLNET_REQUIRE(ArduPilotMissing());
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const std::string station = WlanPrefix(10) + "2";  // robot 1
  const RunScenario scenario = WriteScenario(
      10,
      "robot { name: \"c1\" position_m { x: 0 y: 0 z: 0.1 } ardupilot_json_port: 9002 "
      "image: \"arducopter\" args: [\"--serial0\", \"udpclient:" + station + ":14550\"] }\n"
      "robot { name: \"gcs\" position_m { x: 5 y: 0 z: 0.1 } image: \"" +
          WriteStationImage("guided_flight_lockstep.cjs", {"10", "3", "20", "0"}) + "\" }\n",
      "timing { duration_ms: 50000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  for (const char* run : {"1", "2"}) {
    const CommandResult result = SitlnetRun(scenario, out + run, {});
    ASSERT_EQ(result.exit_code, 0) << result.err;
  }
  const auto same = [&](const std::string& file) {
    const std::string first = ReadAll(out + "1/" + file);
    EXPECT_FALSE(first.empty()) << file;
    EXPECT_TRUE(first == ReadAll(out + "2/" + file)) << file << " differs";
    return first;
  };
  // The station's view: every STATUSTEXT, position report and event, with ArduCopter's time.
  const std::string station_log = same("robots/gcs.log");
  EXPECT_NE(station_log.find("ARMED t="), std::string::npos) << station_log;
  same("trajectories.csv");
  same("deliveries.csv");
  // It flew: robot 0 higher than 3 m at the end.
  const std::vector<TrajectoryRow> path = TrajectoryRows(ReadAll(out + "1/trajectories.csv"), 0);
  ASSERT_FALSE(path.empty());
  EXPECT_GT(path.back().z_m, 3);
  // The capture: the same but for the fields the kernels draw at random.
  const std::string first_pcap = ReadAll(out + "1/medium.pcap");
  EXPECT_GT(first_pcap.size(), 100000u) << "the MAVLink exchange is on the radio";
  const std::string first_masked = WithoutHostDecidedFields(first_pcap);
  const std::string second_masked = WithoutHostDecidedFields(ReadAll(out + "2/medium.pcap"));
  EXPECT_TRUE(first_masked == second_masked) << FirstDifference(first_masked, second_masked);
  // `sitlnet verify` of the two folders says the same of each file.
  const CommandResult verify = RunCommand({SitlnetBinary(), "verify", out + "1", out + "2"});
  for (const char* line : {"trajectories.csv: same\n", "deliveries.csv: same\n",
                           "robots/gcs.log: same\n", "medium.pcap: within bound: "}) {
    EXPECT_NE(verify.out.find(line), std::string::npos) << line << verify.out << verify.err;
  }
  std::printf("sitlnet verify of the two runs (exit %d):\n%s", verify.exit_code,
              verify.out.c_str());
  ExpectNothingLeft(scenario.name);
}

// PX4 v1.14.4, flown by a station in the lock-step (fly_px4_lockstep.cjs): arm, take off to
// 5 m, hold over home; 30 virtual seconds (PX4 arms about 9 s after it connects). Its threads
// make the runs differ (docs/autopilots-evidence.md): the test bounds how far apart.
// The bound, 0.6 m: each run's path is where its own position estimate steers it, to the same
// setpoints (the station acts only on PX4's telemetry and the lock-step fixes when its
// commands arrive). Issue 31 bounds that estimate to 0.3 m of the truth, and Px4FlightTest
// asserts it in every run: two such paths are at most 2 x 0.3 m apart. Compared from lift-off
// (aligned: PX4 arms at a time its threads decide) to the end.
TEST(Px4ReproducibilityTest, TwoLockstepFlightsStayWithinTwiceTheEstimatorBound) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(Px4Missing());
  SITLNET_REQUIRE(NodeMavlinkMissing());
  const RunScenario scenario = WriteScenario(
      11,
      "robot { name: \"px\" position_m { x: 3 y: -2 z: 0.2 } image: \"px4\" "
      "px4_sim_port: 4560 args: [\"--gcs\", \"" + WlanPrefix(11) + "2\"] }\n"  // robot 1
      "robot { name: \"gcs\" position_m { x: 8 y: -2 z: 0.1 } image: \"" +
          WriteStationImage("fly_px4_lockstep.cjs", {"5", "0", "0"}) + "\" }\n",
      "timing { duration_ms: 30000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  std::string trajectories[2];
  for (int run = 0; run < 2; ++run) {
    const std::string folder = out + std::to_string(run + 1);
    const CommandResult result = SitlnetRun(scenario, folder, {});
    ASSERT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(ReadAll(folder + "/robots/gcs.log").find("EVENT ARMED"), std::string::npos)
        << ReadAll(folder + "/robots/gcs.log");
    trajectories[run] = ReadAll(folder + "/trajectories.csv");
    ASSERT_GT(TrajectoryRows(trajectories[run], 0).size(), 200u);
  }
  // Aligned at each run's lift-off, as `sitlnet verify` compares a PX4 run.
  const std::optional<verify::PathGap> gap =
      verify::ComparePathsFromLiftOff(trajectories[0], trajectories[1], 0);
  ASSERT_TRUE(gap && gap->lift_off_s[0] && gap->lift_off_s[1]) << "it lifted off in both runs";
  ASSERT_GE(gap->compared_s, 10) << "less than 10 s of flight to compare";
  double highest_m = 0;
  for (const TrajectoryRow& row : TrajectoryRows(trajectories[0], 0)) {
    highest_m = std::max(highest_m, row.z_m);
  }
  EXPECT_GT(highest_m, 4) << "it climbed towards 5 m";
  EXPECT_LT(gap->worst_m, verify::kPx4PathBoundM);
  // `sitlnet verify` of the two folders: the paths within the bound, nothing said to differ.
  const CommandResult verify = RunCommand({SitlnetBinary(), "verify", out + "1", out + "2"});
  EXPECT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  EXPECT_NE(verify.out.find("trajectories.csv: within bound: a run with PX4: paths at most"),
            std::string::npos)
      << verify.out;
  std::printf("sitlnet verify of the two runs (exit %d):\n%s", verify.exit_code,
              verify.out.c_str());
  std::printf("PX4 lockstep, two runs: lift-off at %.1f s and %.1f s; aligned there, over %.1f s "
              "the paths are at most %.3f m apart (horizontal %.3f m, vertical %.3f m)\n",
              *gap->lift_off_s[0], *gap->lift_off_s[1], gap->compared_s, gap->worst_m,
              gap->worst_horizontal_m, gap->worst_vertical_m);
  ExpectNothingLeft(scenario.name);
}

}  // namespace
}  // namespace sitlnet::nns::testing
