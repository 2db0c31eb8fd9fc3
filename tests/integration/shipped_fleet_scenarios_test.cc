// The shipped fleet scenarios (issue 32: scenarios/px4_fleet.textproto and
// scenarios/ardupilot_fleet.textproto, the autopilot quickstart's, docs/howto-autopilot-fleet.md)
// run as shipped, in lockstep pacing for 15 s of virtual time: the run succeeds, and the ground
// station's relay (the shipped gcs_relay image) hears every one of the four vehicles over the
// radio. The flights themselves are AutopilotFleetTest's.
#include <set>
#include <sstream>
#include <string>
#include <sys/stat.h>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::ReadAll;
using integration_test::SourceDir;
using integration_test::TempDir;

// The gcs_relay image's host folder, as the quickstart makes it; removed afterwards if made here.
constexpr const char* kGcsFolder = "/run/sitlnet-gcs";

// The vehicles the station's relay heard: its log's "vehicle ADDR:PORT" lines, by address.
std::set<std::string> VehiclesHeard(const std::string& relay_log) {
  std::set<std::string> addresses;
  std::istringstream lines(relay_log);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("vehicle ", 0) == 0) addresses.insert(line.substr(8, line.find(':') - 8));
  }
  return addresses;
}

void RunShippedScenario(const std::string& file, const std::string& name) {
  struct stat folder {};
  const bool made_folder = stat(kGcsFolder, &folder) != 0;
  if (made_folder) {
    ASSERT_EQ(mkdir(kGcsFolder, 0755), 0) << kGcsFolder;
  }
  DownGuard guard(name);
  const RunScenario scenario{name, SourceDir() + "/scenarios/" + file};
  const std::string out = TempDir() + "/" + name + "-shipped-out";
  const CommandResult run =
      SitlnetRun(scenario, out, {"--pacing", "lockstep", "--duration", "15"});
  EXPECT_EQ(run.exit_code, 0) << run.err;
  const std::set<std::string> heard = VehiclesHeard(ReadAll(out + "/robots/gcs.log"));
  EXPECT_EQ(heard.size(), 4u) << "the relay heard " << heard.size() << " vehicles";
  RunCommand({"rm", "-rf", out});
  if (made_folder) {
    EXPECT_EQ(rmdir(kGcsFolder), 0) << kGcsFolder;
  }
  ExpectNothingLeft(name);
}

TEST(ShippedFleetScenariosTest, Px4FleetRunsAndItsStationHearsEveryVehicle) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(Px4Missing());
  RunShippedScenario("px4_fleet.textproto", "px4fleet");
}

TEST(ShippedFleetScenariosTest, ArduPilotFleetRunsAndItsStationHearsEveryVehicle) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(ArduPilotMissing());
  RunShippedScenario("ardupilot_fleet.textproto", "apfleet");
}

}  // namespace
}  // namespace sitlnet::nns::testing
