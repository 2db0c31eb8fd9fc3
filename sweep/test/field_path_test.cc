// --set's field paths through reflection: every scalar type, and one clear refusal per mistake.
#include <gtest/gtest.h>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

proto::Scenario ThreeRobots() {
  proto::Scenario spec;
  for (const char* name : {"a", "b", "c"}) spec.add_robot()->set_name(name);
  return spec;
}

std::string ErrorOf(const std::string& path, const std::string& value) {
  proto::Scenario spec = ThreeRobots();
  try {
    SetFieldByPath(path, value, &spec);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(FieldPathTest, SetsEveryScalarType) {
  proto::Scenario spec = ThreeRobots();
  SetFieldByPath("radio.rate_mbps", "6", &spec);                  // double
  SetFieldByPath("timing.duration_ms", "1500", &spec);            // int64
  SetFieldByPath("radio.queue_limit_frames", "20", &spec);        // uint32
  SetFieldByPath("radio.shadowing", "false", &spec);              // bool
  SetFieldByPath("timing.pacing", "PACING_LOCKSTEP", &spec);      // enum
  SetFieldByPath("robot[2].image", "flocker", &spec);             // string
  SetFieldByPath("robot[2].position_m.x", "-2.5", &spec);         // in a message of a list
  EXPECT_EQ(spec.radio().rate_mbps(), 6);
  EXPECT_EQ(spec.timing().duration_ms(), 1500);
  EXPECT_EQ(spec.radio().queue_limit_frames(), 20u);
  EXPECT_TRUE(spec.radio().has_shadowing());
  EXPECT_FALSE(spec.radio().shadowing());
  EXPECT_EQ(spec.timing().pacing(), proto::Timing::PACING_LOCKSTEP);
  EXPECT_EQ(spec.robot(2).image(), "flocker");
  EXPECT_EQ(spec.robot(2).position_m().x(), -2.5);
  EXPECT_FALSE(spec.robot(1).has_position_m());  // Only the element named.
}

TEST(FieldPathTest, RefusesUnknownFields) {
  EXPECT_EQ(ErrorOf("radio.rate", "6"), "Radio has no field \"rate\"");
  EXPECT_EQ(ErrorOf("radoi.rate_mbps", "6"), "Scenario has no field \"radoi\"");
}

TEST(FieldPathTest, RefusesNonScalarsAndListMistakes) {
  EXPECT_EQ(ErrorOf("radio", "6"), "radio is not a scalar field (name one of its fields)");
  EXPECT_EQ(ErrorOf("robot[0].position_m", "1"),
            "robot[0].position_m is not a scalar field (name one of its "
            "fields)");
  EXPECT_EQ(ErrorOf("robot.image", "x"),
            "robot is a list: name one element, robot[INDEX]");
  EXPECT_EQ(ErrorOf("robot[3].image", "x"), "index 3 past the scenario's 3 robot");
  EXPECT_EQ(ErrorOf("radio[0].rate_mbps", "6"), "radio is not a list: no [INDEX]");
  EXPECT_EQ(ErrorOf("radio.rate_mbps.x", "6"), "radio.rate_mbps is a scalar, it has no fields");
  EXPECT_EQ(ErrorOf("robot[0].args", "x"),
            "robot[0].args is a list: name one element, robot[0].args[INDEX]");
}

TEST(FieldPathTest, RefusesValuesOfTheWrongType) {
  EXPECT_EQ(ErrorOf("radio.rate_mbps", "fast"), "\"fast\" is not a number");
  EXPECT_EQ(ErrorOf("radio.rate_mbps", "6x"), "\"6x\" is not a number");
  EXPECT_EQ(ErrorOf("radio.rate_mbps", "nan"), "\"nan\" is not a number");
  EXPECT_EQ(ErrorOf("timing.duration_ms", "1.5"), "\"1.5\" is not an integer");
  EXPECT_EQ(ErrorOf("radio.queue_limit_frames", "-1"),
            "\"-1\" is not a non-negative integer");
  EXPECT_EQ(ErrorOf("radio.queue_limit_frames", "4294967296"),
            "\"4294967296\" is not a non-negative integer");
  EXPECT_EQ(ErrorOf("radio.shadowing", "1"), "\"1\" is not true or false");
  EXPECT_EQ(ErrorOf("timing.pacing", "FAST"), "\"FAST\" is not one of PACING_REALTIME, PACING_LOCKSTEP");
}

}  // namespace
}  // namespace sitlnet::sweep
