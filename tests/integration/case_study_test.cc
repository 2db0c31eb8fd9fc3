// The DANCERS case study (docs/case-study.md): four flockers cross the arrow
// obstacle. With radio shadowing the communication graph splits into groups
// that are far apart and reunites past the obstacle; without shadowing it
// stays one component. Measured from the medium's delivery log
// (connectivity.csv) and the trajectories, in lockstep pacing.
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

struct Sample {
  int components = 0;
  std::vector<int> component_of;
};

// connectivity.csv: time_s,components,robot_0..robot_3 -> by time in ms.
std::map<long, Sample> ReadConnectivity(const std::string& path) {
  std::map<long, Sample> samples;
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  while (std::getline(file, line)) {
    std::stringstream row(line);
    std::string cell;
    std::getline(row, cell, ',');
    const long time_ms = std::lround(std::stod(cell) * 1000);
    Sample sample;
    std::getline(row, cell, ',');
    sample.components = std::stoi(cell);
    while (std::getline(row, cell, ',')) sample.component_of.push_back(std::stoi(cell));
    samples[time_ms] = sample;
  }
  return samples;
}

// trajectories.csv -> by time in ms, per robot (x, y).
std::map<long, std::map<int, std::pair<double, double>>> ReadTrajectories(const std::string& path) {
  std::map<long, std::map<int, std::pair<double, double>>> positions;
  std::ifstream file(path);
  std::string line;
  std::getline(file, line);
  while (std::getline(file, line)) {
    double time_s, x, y;
    int robot;
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%lf", &time_s, &robot, &x, &y) == 4) {
      positions[std::lround(time_s * 1000)][robot] = {x, y};
    }
  }
  return positions;
}

// The case study under a name and subnets of this process (scenario names are global: a demo
// or another test run flying "arrow" at the same time must not clash), otherwise unchanged.
struct CaseStudy {
  std::string name;
  std::string path;
};
CaseStudy WriteCaseStudy(int slot) {
  const unsigned pid = static_cast<unsigned>(getpid());
  CaseStudy study;
  study.name = "cs" + std::to_string(pid % 10000) + std::to_string(slot);
  const char* source = std::getenv("SITLNET_SOURCE_DIR");
  std::string text =
      ReadAll(std::string(source ? source : ".") + "/scenarios/arrow_flocking.textproto");
  const std::string original = "name: \"arrow\"";
  const size_t at = text.find(original);
  EXPECT_NE(at, std::string::npos) << "scenarios/arrow_flocking.textproto has no " << original;
  if (at != std::string::npos) text.replace(at, original.size(), "name: \"" + study.name + "\"");
  const std::string third = std::to_string(pid % 250);
  text += "addresses { wlan_subnet: \"10." + std::to_string(236 + slot) + "." + third +
          ".0/24\" ctl_subnet: \"10." + std::to_string(196 + slot) + "." + third + ".0/24\" }\n";
  study.path = TempDir() + "/" + study.name + ".textproto";
  std::ofstream(study.path) << text;
  return study;
}

std::string RunCaseStudy(const CaseStudy& study, const std::vector<std::string>& extra) {
  const std::string out = TempDir() + "/" + study.name + "-out";
  std::vector<std::string> argv = {SitlnetBinary(), "run",      study.path,     "--out", out,
                                   "--pacing",      "lockstep", "--no-progress"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  const CommandResult result = RunCommand(argv, 900 * kNsPerS);
  EXPECT_EQ(result.exit_code, 0) << result.err;
  return out;
}

TEST(CaseStudyTest, ShadowingSplitsTheFleetAndItReunitesPastTheArrow) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const CaseStudy study = WriteCaseStudy(0);
  DownGuard guard(study.name);
  const std::string out = RunCaseStudy(study, {});
  const auto connectivity = ReadConnectivity(out + "/connectivity.csv");
  const auto positions = ReadTrajectories(out + "/trajectories.csv");
  ASSERT_FALSE(connectivity.empty());
  long split_ms = 0, first_split_ms = -1;
  double widest_gap_m = 0;
  for (const auto& [time_ms, sample] : connectivity) {
    if (sample.components < 2) continue;
    split_ms += 100;
    if (first_split_ms < 0) first_split_ms = time_ms;
    // Distance between the closest robots of different groups: how far apart
    // the groups really are while they cannot hear each other.
    const auto at = positions.find(time_ms);
    if (at == positions.end()) continue;
    double closest = INFINITY;
    for (const auto& [a, pa] : at->second) {
      for (const auto& [b, pb] : at->second) {
        if (sample.component_of[a] == sample.component_of[b]) continue;
        closest = std::min(closest, std::hypot(pa.first - pb.first, pa.second - pb.second));
      }
    }
    if (std::isfinite(closest)) widest_gap_m = std::max(widest_gap_m, closest);
  }
  // The groups lose contact for a sustained stretch, not a lost beacon or two
  // (the window is 2 s, 20 beacons), ...
  EXPECT_GE(split_ms, 10'000) << "split for " << split_ms << " ms";
  // ... while far apart on either side of the arrow (its arms are 32 m long),
  EXPECT_GE(widest_gap_m, 25.0);
  // ... and reunite: one component at the end of the run.
  EXPECT_EQ(connectivity.rbegin()->second.components, 1);
  EXPECT_GT(first_split_ms, 0);
}

TEST(CaseStudyTest, WithoutShadowingTheFleetStaysConnected) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const CaseStudy study = WriteCaseStudy(1);
  DownGuard guard(study.name);
  const std::string out = RunCaseStudy(study, {"--no-shadowing"});
  const auto connectivity = ReadConnectivity(out + "/connectivity.csv");
  ASSERT_GE(connectivity.size(), 1000u);  // 130 s at 100 ms
  for (const auto& [time_ms, sample] : connectivity) {
    ASSERT_EQ(sample.components, 1) << "split at t=" << time_ms << " ms";
  }
}

}  // namespace
}  // namespace sitlnet::nns::testing
