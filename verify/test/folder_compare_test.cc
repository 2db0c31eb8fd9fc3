// CompareRunFolders and the record's checks on run folders made by hand: each kind of output
// gets its rule, and a file changed after its run is caught by its recorded hash.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <fstream>
#include <map>
#include <string>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

// The scenario as run, as a JSON string (escaped quotes and newlines).
constexpr char kScenario[] =
    R"(name: \"fc\"\nrobot {\n  name: \"a\"\n}\ntiming {\n  pacing: PACING_LOCKSTEP\n}\n)";

// A run folder holding `files`, with a summary.json recording each one's hash.
std::string MakeRun(const std::string& name, const std::map<std::string, std::string>& files,
                    const std::string& pacing = "PACING_LOCKSTEP") {
  const std::string dir = ::testing::TempDir() + "/" + name + std::to_string(getpid());
  mkdir(dir.c_str(), 0755);
  mkdir((dir + "/robots").c_str(), 0755);
  std::string outputs;
  for (const auto& [path, bytes] : files) {
    std::ofstream(dir + "/" + path, std::ios::binary) << bytes;
    outputs += (outputs.empty() ? "\"" : ",\"") + path + "\":{\"sha256\":\"" +
               Sha256HexOfFile(dir + "/" + path) + "\",\"bytes\":" +
               std::to_string(bytes.size()) + "}";
  }
  std::ofstream(dir + "/summary.json")
      << "{\"scenario\":\"fc\",\"source\":\"fc.textproto\",\"pacing\":\"" << pacing
      << "\",\"seed\":5,\"sitlnet_version\":\"unknown\",\"scenario_text\":\"" << kScenario
      << "\",\"interrupted\":false,\"failure\":null,\"outputs\":{" << outputs << "}}\n";
  return dir;
}

std::map<std::string, std::string> SomeOutputs() {
  return {{"trajectories.csv", "time_s,robot,x_m\n0.000,0,1.000\n0.100,0,1.010\n"},
          {"metrics.csv", "iteration,start_ns,t_phy_ns\n0,0,812345\n"},
          {"robots/a.log", "flocker up\n"}};
}

std::map<std::string, OutputVerdict> ByPath(const std::vector<OutputVerdict>& verdicts) {
  std::map<std::string, OutputVerdict> by_path;
  for (const OutputVerdict& v : verdicts) by_path[v.path] = v;
  return by_path;
}

TEST(FolderCompareTest, TheSameRunIsTheSameButForWallClockTimings) {
  std::map<std::string, std::string> second = SomeOutputs();
  second["metrics.csv"] = "iteration,start_ns,t_phy_ns\n0,0,799000\n";
  const auto verdicts = ByPath(CompareRunFolders(ReadRunRecord(MakeRun("same_a", SomeOutputs())),
                                                 ReadRunRecord(MakeRun("same_b", second))));
  ASSERT_EQ(verdicts.size(), 3u);
  EXPECT_EQ(verdicts.at("trajectories.csv").verdict, Verdict::kSame);
  EXPECT_EQ(verdicts.at("robots/a.log").verdict, Verdict::kSame);
  EXPECT_EQ(verdicts.at("metrics.csv").verdict, Verdict::kNotCompared);
}

TEST(FolderCompareTest, AByteChangedAfterTheRunDiffersAndIsNamed) {
  const std::string a = MakeRun("changed_a", SomeOutputs());
  const std::string b = MakeRun("changed_b", SomeOutputs());
  {
    std::fstream file(b + "/trajectories.csv", std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(20);
    file.put('9');
  }
  const auto verdicts = ByPath(CompareRunFolders(ReadRunRecord(a), ReadRunRecord(b)));
  EXPECT_EQ(verdicts.at("trajectories.csv").verdict, Verdict::kDiffers);
  EXPECT_NE(verdicts.at("trajectories.csv").detail.find("changed since its run"),
            std::string::npos)
      << verdicts.at("trajectories.csv").detail;
  EXPECT_EQ(verdicts.at("robots/a.log").verdict, Verdict::kSame);
}

TEST(FolderCompareTest, ADifferentRunDiffersAtItsFirstRow) {
  std::map<std::string, std::string> second = SomeOutputs();
  second["trajectories.csv"] = "time_s,robot,x_m\n0.000,0,1.000\n0.100,0,1.020\n";
  second["robots/b.log"] = "another robot\n";
  const auto verdicts = ByPath(CompareRunFolders(ReadRunRecord(MakeRun("diff_a", SomeOutputs())),
                                                 ReadRunRecord(MakeRun("diff_b", second))));
  EXPECT_EQ(verdicts.at("trajectories.csv").verdict, Verdict::kDiffers);
  EXPECT_EQ(verdicts.at("trajectories.csv").detail.rfind("first at row 2 (time_s 0.100)", 0), 0u)
      << verdicts.at("trajectories.csv").detail;
  EXPECT_EQ(verdicts.at("robots/b.log").verdict, Verdict::kDiffers);
  // A rerun is held to what the original recorded: its extra file is not compared.
  const auto recorded = ByPath(CompareRunFolders(ReadRunRecord(MakeRun("diff_a", SomeOutputs())),
                                                 ReadRunRecord(MakeRun("diff_b", second)),
                                                 OutputSet::kReference));
  EXPECT_EQ(recorded.count("robots/b.log"), 0u);
  EXPECT_EQ(recorded.at("trajectories.csv").verdict, Verdict::kDiffers);
}

TEST(FolderCompareTest, ARealtimeRunIsRefusedInOneLine) {
  const RunRecord record = ReadRunRecord(MakeRun("realtime", SomeOutputs(), "PACING_REALTIME"));
  try {
    RefuseUnreproducible(record);
    FAIL() << "not refused";
  } catch (const Error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("PACING_REALTIME"), std::string::npos) << message;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
  }
}

TEST(FolderCompareTest, ASummaryWithoutARecordIsNamed) {
  const std::string dir = ::testing::TempDir() + "/no_record" + std::to_string(getpid());
  mkdir(dir.c_str(), 0755);
  std::ofstream(dir + "/summary.json") << "{\"scenario\":\"old\",\"pacing\":\"PACING_LOCKSTEP\"}";
  try {
    ReadRunRecord(dir);
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find(dir + "/summary.json: no run record"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace sitlnet::verify
