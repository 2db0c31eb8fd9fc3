// `sitlnet verify` end to end (docs/sweep.md, "Check that a run reproduces"): a 2 s lockstep run
// of two flockers is rerun and found the same; one byte changed in trajectories.csv is found and
// named, comparing two folders and by a rerun; a realtime run is refused. The oracle of "same" is the run record's own claim, checked
// against coreutils' sha256sum.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::ReadAll;
using integration_test::TempDir;

// Byte `at` of the file at `path` made another digit (or a digit where it was not one).
void ChangeOneByte(const std::string& path, std::streamoff at) {
  std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
  file.seekg(at);
  const char byte = static_cast<char>(file.get());
  file.seekp(at);
  file.put(byte == '1' ? '2' : '1');
}

TEST(VerifyTest, ALockstepRunReproducesAndAChangedByteIsNamed) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(6, kTwoFlockers, "timing { duration_ms: 2000 }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  // Slot 6 is also the restart test's: in one process both name the same folder, and a run
  // appends to the robots' logs it finds there.
  RunCommand({"rm", "-rf", out, out + "-rerun"});
  const CommandResult run = SitlnetRun(scenario, out, {"--pacing", "lockstep", "--seed", "5"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  // The record holds what sha256sum computes of the file.
  const std::string summary = ReadAll(out + "/summary.json");
  const CommandResult sha256sum = RunCommand({"sha256sum", out + "/trajectories.csv"});
  ASSERT_EQ(sha256sum.exit_code, 0) << sha256sum.err;
  const std::string trajectories_hash = sha256sum.out.substr(0, 64);
  EXPECT_NE(summary.find("\"trajectories.csv\":{\"sha256\":\"" + trajectories_hash + "\""),
            std::string::npos)
      << summary;

  const CommandResult verify = RunCommand(
      {SitlnetBinary(), "verify", out, "--out", out + "-rerun", "--no-progress"}, 120 * kNsPerS);
  EXPECT_EQ(verify.exit_code, 0) << verify.out << verify.err;
  for (const char* line : {"trajectories.csv: same\n", "medium.pcap: same\n",
                           "deliveries.csv: same\n", "robots/a.log: same\n",
                           "scenario.textproto: same\n", "losses.csv.gz: same\n"}) {
    EXPECT_NE(verify.out.find(line), std::string::npos) << line << verify.out;
  }
  EXPECT_NE(verify.out.find(" 0 differ: reproduced\n"), std::string::npos) << verify.out;

  // One byte of the rerun's trajectories.csv changed: the two folders compared differ there.
  ChangeOneByte(out + "-rerun/trajectories.csv", 200);
  const CommandResult changed =
      RunCommand({SitlnetBinary(), "verify", out, out + "-rerun"}, 30 * kNsPerS);
  EXPECT_EQ(changed.exit_code, 1) << changed.out << changed.err;
  EXPECT_NE(changed.out.find("trajectories.csv: differs: changed since its run"),
            std::string::npos)
      << changed.out;
  EXPECT_NE(changed.out.find("medium.pcap: same\n"), std::string::npos) << changed.out;

  // The same byte changed in the run's own folder: its rerun names the file too.
  ChangeOneByte(out + "/trajectories.csv", 200);
  const CommandResult rerun = RunCommand(
      {SitlnetBinary(), "verify", out, "--out", out + "-rerun2", "--no-progress"}, 120 * kNsPerS);
  EXPECT_EQ(rerun.exit_code, 1) << rerun.out << rerun.err;
  EXPECT_NE(rerun.out.find("trajectories.csv: differs: changed since its run: " + out +
                           "/trajectories.csv"),
            std::string::npos)
      << rerun.out;
  EXPECT_NE(rerun.out.find(" 1 differ: not reproduced\n"), std::string::npos) << rerun.out;
  ExpectNothingLeft(scenario.name);
}

TEST(VerifyTest, ARealtimeRunIsRefusedInOneLine) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RunScenario scenario = WriteScenario(7, kTwoFlockers, "timing { duration_ms: 500 }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult run = SitlnetRun(scenario, out, {"--pacing", "realtime"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CommandResult verify = RunCommand({SitlnetBinary(), "verify", out}, 30 * kNsPerS);
  EXPECT_EQ(verify.exit_code, 2) << verify.out << verify.err;
  EXPECT_EQ(verify.err, "sitlnet verify: " + out +
                            " was run in PACING_REALTIME: its outputs follow the host's timing, "
                            "so no run reproduces them; verify checks lockstep runs (sitlnet run "
                            "--pacing lockstep)\n");
  EXPECT_TRUE(verify.out.empty()) << verify.out;
  ExpectNothingLeft(scenario.name);
}

}  // namespace
}  // namespace sitlnet::nns::testing
