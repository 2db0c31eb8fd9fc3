// --set robot_count=N: a point keeps the scenario's first N robots; a count the scenario cannot
// give is refused in one line, and robot_count applies before the other fields.
#include <gtest/gtest.h>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

proto::Scenario FourRobots() {
  proto::Scenario spec;
  for (const char* name : {"a", "b", "c", "d"}) spec.add_robot()->set_name(name);
  spec.add_obstacle()->set_name("wall");
  return spec;
}

std::string ErrorOf(const std::string& value) {
  proto::Scenario spec = FourRobots();
  try {
    KeepFirstRobots(value, &spec);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(RobotCountTest, KeepsTheFirstRobotsInTheirOrderAndEverythingElse) {
  proto::Scenario spec = FourRobots();
  SetAxisValue("robot_count", "2", &spec);
  ASSERT_EQ(spec.robot_size(), 2);
  EXPECT_EQ(spec.robot(0).name(), "a");
  EXPECT_EQ(spec.robot(1).name(), "b");
  EXPECT_EQ(spec.obstacle_size(), 1);
  proto::Scenario all = FourRobots();
  SetAxisValue("robot_count", "4", &all);
  EXPECT_EQ(all.robot_size(), 4);
}

TEST(RobotCountTest, RefusesCountsTheScenarioCannotGive) {
  const std::string why =
      "is not a robot count from 1 to the 4 robots the scenario lists (robot_count keeps the "
      "first N)";
  for (const char* value : {"0", "5", "-1", "2.5", "two", "", "1000000000000"}) {
    EXPECT_EQ(ErrorOf(value), "\"" + std::string(value) + "\" " + why) << value;
  }
}

// The pseudo-field would hide a schema field of the same name: if the schema gains one, this
// fails and the pseudo-field needs another name.
TEST(RobotCountTest, TheSchemaHasNoFieldOfThatName) {
  EXPECT_EQ(proto::Scenario::descriptor()->FindFieldByName(kRobotCountField), nullptr);
}

}  // namespace
}  // namespace sitlnet::sweep
