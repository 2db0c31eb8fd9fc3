// The DANCERS case study (docs/case-study.md; Balaguer et al., Sec. VI and Fig. 6): four
// flockers cross the arrow-shaped obstacle, once with radio shadowing and once without, in
// lockstep pacing, for several seeds. The oracle is the paper's account of its figure: with
// shadowing the obstacle blocks the messages, the fleet splits into two subgroups after tau = 2 s
// which go their own ways until the end of the obstacle and then reunite; without it the UAVs
// keep attracting each other, one subgroup turns back to the other and the fleet gets around the
// obstacle without fragmentation. Measured from the medium's delivery log (connectivity.csv)
// and the trajectories.
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

// From scenarios/arrow_flocking.textproto and the paper.
constexpr double kTipX_m = 8.5;         // The head's tip, facing the fleet.
constexpr double kShaftMiddleX_m = 60;  // Robots there are on one side of the shaft or the other.
constexpr double kArrowEndX_m = 90;     // The shaft's far end.
constexpr double kBesideHeadY_m = 3;    // Further than this from the axis: beside the head.
constexpr long kTau_ms =
    2000;  // The paper's neighbour lifetime, the flocker's --neighbour-timeout-s.
constexpr int kRobots = 4;

struct Sample {
  int components = 0;
  std::vector<int> component_of;
};

struct Position {
  double x_m = 0, y_m = 0;
};

struct Outcome {
  std::map<long, Sample> connectivity;                // By time in ms.
  std::map<long, std::map<int, Position>> positions;  // By time in ms, then robot.
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

// trajectories.csv -> by time in ms, per robot.
std::map<long, std::map<int, Position>> ReadTrajectories(const std::string& path) {
  std::map<long, std::map<int, Position>> positions;
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
  std::string text = ReadAll(integration_test::SourceDir() + "/scenarios/arrow_flocking.textproto");
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

// Runs the case study with and without shadowing side by side: a lockstep run spends most of
// its time waiting for the robots' answers (about 14 s of CPU for 40 s of wall time here), so
// two at once take little longer than one. Three or more at once on a 2-core host made robots
// miss the coordinator's 1 s answer deadline while starting.
std::pair<Outcome, Outcome> RunBothVariants(uint64_t seed) {
  const CaseStudy shadowing = WriteCaseStudy(0);
  const CaseStudy no_shadowing = WriteCaseStudy(1);
  DownGuard guard_a(shadowing.name);
  DownGuard guard_b(no_shadowing.name);
  auto argv = [&](const CaseStudy& study, bool shadow) {
    std::vector<std::string> args = {SitlnetBinary(),
                                     "run",
                                     study.path,
                                     "--out",
                                     TempDir() + "/" + study.name + "-out",
                                     "--pacing",
                                     "lockstep",
                                     "--no-progress",
                                     "--seed",
                                     std::to_string(seed)};
    if (!shadow) args.push_back("--no-shadowing");
    return args;
  };
  integration_test::Child with(argv(shadowing, true));
  integration_test::Child without(argv(no_shadowing, false));
  EXPECT_EQ(with.Wait(900 * kNsPerS), 0) << with.err();
  EXPECT_EQ(without.Wait(900 * kNsPerS), 0) << without.err();
  auto read = [](const CaseStudy& study) {
    const std::string out = TempDir() + "/" + study.name + "-out";
    return Outcome{ReadConnectivity(out + "/connectivity.csv"),
                   ReadTrajectories(out + "/trajectories.csv")};
  };
  return {read(shadowing), read(no_shadowing)};
}

// Longest stretch of consecutive samples with more than one component, in ms.
long LongestSplit_ms(const std::map<long, Sample>& connectivity) {
  long longest = 0, start = -1, previous = -1;
  for (const auto& [time_ms, sample] : connectivity) {
    if (sample.components > 1) {
      if (start < 0) start = previous >= 0 ? previous : time_ms;
      longest = std::max(longest, time_ms - start);
    } else {
      start = -1;
    }
    previous = time_ms;
  }
  return longest;
}

// Whether, at some instant, robots past the tip were beside the head on both sides: the fleet
// met the arrow split by its tip.
bool StraddledTheHead(const Outcome& o) {
  for (const auto& [time_ms, robots] : o.positions) {
    bool north = false, south = false;
    for (const auto& [robot, p] : robots) {
      if (p.x_m <= kTipX_m) continue;
      north |= p.y_m > kBesideHeadY_m;
      south |= p.y_m < -kBesideHeadY_m;
    }
    if (north && south) return true;
  }
  return false;
}

// Per robot, the side (+1 north, -1 south) on which it first reached the middle of the shaft;
// 0 if it never did.
std::map<int, int> ShaftSides(const Outcome& o) {
  std::map<int, int> side;
  for (const auto& [time_ms, robots] : o.positions) {
    for (const auto& [robot, p] : robots) {
      if (!side.count(robot) && p.x_m >= kShaftMiddleX_m) side[robot] = p.y_m > 0 ? 1 : -1;
    }
  }
  for (int robot = 0; robot < kRobots; ++robot) side.emplace(robot, 0);
  return side;
}

bool AllPastTheArrow(const Outcome& o) {
  if (o.positions.empty()) return false;
  const auto& last = o.positions.rbegin()->second;
  if (last.size() != size_t(kRobots)) return false;
  for (const auto& [robot, p] : last) {
    if (p.x_m <= kArrowEndX_m) return false;
  }
  return true;
}

class CaseStudyTest : public ::testing::TestWithParam<uint64_t> {};

TEST_P(CaseStudyTest, ShadowingSplitsAndReunitesWithoutItTheFleetGoesAroundAsOneGroup) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const auto [with, without] = RunBothVariants(GetParam());
  ASSERT_GE(with.connectivity.size(), 1000u);
  ASSERT_GE(without.connectivity.size(), 1000u);

  // Both fleets meet the arrow the same way: split by its tip.
  EXPECT_TRUE(StraddledTheHead(with));
  EXPECT_TRUE(StraddledTheHead(without));

  // With shadowing: the obstacle blocks the messages for longer than tau, ...
  EXPECT_GE(LongestSplit_ms(with.connectivity), kTau_ms);
  // ... between robots on opposite sides of the arrow while they fly along it (the split is
  // the obstacle's doing), ...
  int same_side = 0;
  std::string example;
  for (const auto& [time_ms, sample] : with.connectivity) {
    if (sample.components < 2 || !with.positions.count(time_ms)) continue;
    const auto& robots = with.positions.at(time_ms);
    for (const auto& [a, pa] : robots) {
      for (const auto& [b, pb] : robots) {
        const bool along =
            std::min(pa.x_m, pb.x_m) > kTipX_m && std::max(pa.x_m, pb.x_m) < kArrowEndX_m;
        if (!along || sample.component_of[a] == sample.component_of[b] || pa.y_m * pb.y_m < 0) {
          continue;
        }
        if (same_side++ == 0) {
          example = "robots " + std::to_string(a) + " and " + std::to_string(b) +
                    " at t=" + std::to_string(time_ms) + " ms";
        }
      }
    }
  }
  EXPECT_EQ(same_side, 0) << "split on the same side of the arrow, e.g. " << example;
  // ... the subgroups pass the shaft on either side, ...
  std::set<int> sides_with;
  for (const auto& [robot, side] : ShaftSides(with)) sides_with.insert(side);
  EXPECT_EQ(sides_with, (std::set<int>{-1, 1}));
  // ... and reunite past the arrow.
  EXPECT_EQ(with.connectivity.rbegin()->second.components, 1);
  EXPECT_TRUE(AllPastTheArrow(with));

  // Without shadowing: never disconnected, ...
  for (const auto& [time_ms, sample] : without.connectivity) {
    ASSERT_EQ(sample.components, 1) << "split at t=" << time_ms << " ms";
  }
  // ... one subgroup turned back: every robot passes the shaft on the same side, ...
  std::set<int> sides_without;
  for (const auto& [robot, side] : ShaftSides(without)) sides_without.insert(side);
  EXPECT_EQ(sides_without.size(), 1u);
  EXPECT_EQ(sides_without.count(0), 0u);
  // ... and the fleet gets past the arrow.
  EXPECT_TRUE(AllPastTheArrow(without));
}

// Seed 1 is flown by scripts/test's paper stage (scripts/reproduce-paper --quick: the same
// scenario, seed and flags, so the same runs byte for byte), whose Fig. 6 verdicts check it.
INSTANTIATE_TEST_SUITE_P(Seeds, CaseStudyTest, ::testing::Values(2, 3));

}  // namespace
}  // namespace sitlnet::nns::testing
