// --set and --seeds parsing, the grid's order and the point folders' names.
#include <gtest/gtest.h>

#include <set>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

std::string ErrorOf(const std::function<void()>& body) {
  try {
    body();
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(ValueGridTest, ParsesASetFlag) {
  const SweepAxis axis = ParseSetFlag("robot[2].position_m.x=0,2.5,-1");
  EXPECT_EQ(axis.field_path, "robot[2].position_m.x");
  EXPECT_EQ(axis.values, (std::vector<std::string>{"0", "2.5", "-1"}));
}

TEST(ValueGridTest, RefusesMalformedSetFlagsNamingThem) {
  EXPECT_EQ(ErrorOf([] { ParseSetFlag("radio.rate_mbps"); }),
            "--set radio.rate_mbps: expected FIELD=V1,V2,...");
  EXPECT_EQ(ErrorOf([] { ParseSetFlag("=6"); }), "--set =6: expected FIELD=V1,V2,...");
  EXPECT_EQ(ErrorOf([] { ParseSetFlag("radio.rate_mbps=6,,54"); }),
            "--set radio.rate_mbps=6,,54: an empty value");
  EXPECT_EQ(ErrorOf([] { ParseSetFlag("radio.rate_mbps=6,6"); }),
            "--set radio.rate_mbps=6,6: value \"6\" twice");
}

TEST(ValueGridTest, ParsesSeedRangesAndLists) {
  EXPECT_EQ(ParseSeedList("1-20").size(), 20u);
  EXPECT_EQ(ParseSeedList("7"), (std::vector<uint64_t>{7}));
  EXPECT_EQ(ParseSeedList("9,1-3,2"), (std::vector<uint64_t>{1, 2, 3, 9}));
  EXPECT_NE(ErrorOf([] { ParseSeedList("3-1"); }).find("ends before it starts"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSeedList("a"); }).find("--seeds a"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSeedList("-1"); }).find("not N or N-M"), std::string::npos);
  EXPECT_NE(ErrorOf([] { ParseSeedList("1-999999999"); }).find("more than"), std::string::npos);
}

TEST(ValueGridTest, ExpandsEveryCombinationTimesEverySeed) {
  const std::vector<SweepAxis> axes = {{"radio.rate_mbps", {"6", "54"}},
                                       {"timing.iteration_us", {"5000", "10000", "20000"}}};
  const std::vector<SweepPoint> points = ExpandGrid(axes, {1, 2});
  ASSERT_EQ(points.size(), 12u);
  // The first axis varies slowest, the seed fastest.
  EXPECT_EQ(points[0].values, (std::vector<std::string>{"6", "5000"}));
  EXPECT_EQ(points[0].seed, 1u);
  EXPECT_EQ(points[1].seed, 2u);
  EXPECT_EQ(points[1].combination, 0);
  EXPECT_EQ(points[2].values, (std::vector<std::string>{"6", "10000"}));
  EXPECT_EQ(points[11].values, (std::vector<std::string>{"54", "20000"}));
  EXPECT_EQ(points[11].combination, 5);
  EXPECT_EQ(points[11].folder, "radio.rate_mbps=54,timing.iteration_us=20000,seed=2");
  std::set<std::string> folders;
  for (const SweepPoint& point : points) folders.insert(point.folder);
  EXPECT_EQ(folders.size(), points.size());
}

TEST(ValueGridTest, NoAxesIsOneCombinationOverTheSeeds) {
  const std::vector<SweepPoint> points = ExpandGrid({}, {3, 4});
  ASSERT_EQ(points.size(), 2u);
  EXPECT_EQ(points[1].folder, "seed=4");
}

TEST(ValueGridTest, EscapesSlashesInFolderNames) {
  const std::vector<SweepAxis> axes = {{"addresses.wlan_subnet", {"10.1.0.0/24", "a%b"}}};
  EXPECT_EQ(PointFolderName(axes, {"10.1.0.0/24"}, 1), "addresses.wlan_subnet=10.1.0.0%2F24,seed=1");
  EXPECT_EQ(PointFolderName(axes, {"a%b"}, 1), "addresses.wlan_subnet=a%25b,seed=1");
  EXPECT_NE(ErrorOf([&] { PointFolderName(axes, {std::string(300, 'x')}, 1); }).find("longer than"),
            std::string::npos);
}

}  // namespace
}  // namespace sitlnet::sweep
