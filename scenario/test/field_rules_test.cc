// The rules scenario.proto's field options declare: every default obeys them, and a file that
// breaks one is refused with the line, the field and the rule (field_rules.h).
#include "scenario/field_rules.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "scenario/scenario.h"
#include "sitlnet/field_options.pb.h"

namespace sitlnet {
namespace {

using google::protobuf::FieldDescriptor;

// Loading `text` fails with exactly `message`.
void ExpectMessage(const std::string& text, const std::string& message) {
  try {
    LoadScenarioText(text, "t.textproto");
    FAIL() << "accepted: " << text;
  } catch (const Error& error) {
    EXPECT_EQ(error.what(), message);
  }
}

constexpr char kOne[] = "name: \"t\"\nrobot { name: \"a\" }\n";

// A default outside its own range would be refused in every file that leaves the field out;
// field_rules.cc relies on this to check unset fields only by their default.
TEST(FieldRulesTest, EveryDefaultLiesInItsDeclaredRange) {
  const google::protobuf::FileDescriptor* file = proto::Scenario::descriptor()->file();
  int checked = 0;
  for (int m = 0; m < file->message_type_count(); ++m) {
    const google::protobuf::Descriptor* message = file->message_type(m);
    for (int f = 0; f < message->field_count(); ++f) {
      const FieldDescriptor* field = message->field(f);
      const FieldDescriptor* rules_field = scenario_internal::RulesOf(field);  // Resolves.
      ASSERT_NE(rules_field, nullptr) << field->full_name();
      if (!field->has_default_value()) continue;
      const auto& rules = rules_field->options();
      double value = 0;
      if (field->cpp_type() == FieldDescriptor::CPPTYPE_DOUBLE) {
        value = field->default_value_double();
      } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_INT64) {
        value = static_cast<double>(field->default_value_int64());
      } else if (field->cpp_type() == FieldDescriptor::CPPTYPE_UINT32) {
        value = field->default_value_uint32();
      } else {
        continue;
      }
      if (rules.HasExtension(proto::range_min)) {
        const double min = rules.GetExtension(proto::range_min);
        EXPECT_TRUE(rules.GetExtension(proto::range_min_open) ? value > min : value >= min)
            << field->full_name();
        ++checked;
      }
      if (rules.HasExtension(proto::range_max)) {
        EXPECT_LE(value, rules.GetExtension(proto::range_max)) << field->full_name();
      }
    }
  }
  EXPECT_GT(checked, 10);
}

// kMaxDurationMs is a C++ constant (the remote medium and the CLI bound times with it at compile
// time); the proto's bounds of durations must be the same number.
TEST(FieldRulesTest, DurationBoundIsKMaxDurationMs) {
  for (const google::protobuf::FieldDescriptor* field :
       {proto::Timing::descriptor()->FindFieldByName("duration_ms"),
        proto::Robot::descriptor()->FindFieldByName("command_timeout_ms")}) {
    EXPECT_EQ(field->options().GetExtension(proto::range_max), static_cast<double>(kMaxDurationMs))
        << field->full_name();
  }
}

TEST(FieldRulesTest, MessagesNameTheFieldTheValueAndTheRule) {
  const std::string one = kOne;
  ExpectMessage(one + "radio { tx_power_dbm: 40 }\n",
                "t.textproto:3:9: radio: tx_power_dbm 40 out of range [-10, 30]");
  ExpectMessage(one + "radio { queue_limit_frames: 0 }\n",
                "t.textproto:3:9: radio: queue_limit_frames 0 must be >= 1");
  ExpectMessage(one + "timing { iteration_us: 0 }\n",
                "t.textproto:3:10: timing: iteration_us 0 must be > 0");
  ExpectMessage(one + "timing { physics_step_us: 60000001 }\n",
                "t.textproto:3:10: timing: physics_step_us 60000001 must be at most 60000000");
  ExpectMessage(one + "radio { capture_margin_db: nan }\n",
                "t.textproto:3:9: radio: capture_margin_db nan out of range [0, 100]");
  // The default rate of 802.11a is no rate of 802.11b: a default is checked too.
  ExpectMessage(one + "radio { standard: STANDARD_80211B }\n",
                "t.textproto:3:1: radio: rate_mbps 54 is not a rate of STANDARD_80211B"
                " (802.11a: 6 9 12 18 24 36 48 54; 802.11b: 1 2 5.5 11; 802.11g: both)");
}

// Airframes, obstacles and a robot's sub-messages (lidar, IMU, GPS) are walked the same way: the
// sub-message's name prefixes the field.
TEST(FieldRulesTest, NestedAndRepeatedMessagesNameTheirPlace) {
  ExpectMessage("name: \"t\"\nairframe { name: \"x\" mass_kg: 0 }\nrobot { name: \"a\" }\n",
                "t.textproto:2:22: airframe \"x\": mass_kg 0 must be > 0");
  ExpectMessage("name: \"t\"\nrobot { name: \"a\" lidar { fov_deg: 361 } }\n",
                "t.textproto:2:27: robot \"a\": lidar fov_deg 361 out of range [0.01, 360]");
  ExpectMessage(std::string(kOne) + "obstacle { size_m { x: 1 y: 1 z: 1 } yaw_deg: 2e6 }\n",
                "t.textproto:3:38: obstacle 0: yaw_deg 2e+06 out of range [-1e+06, 1e+06]");
}

// A robot's radio override takes the radio field's rules (same_rules_as), message and all.
TEST(FieldRulesTest, RobotOverridesFollowTheRadioFieldsRules) {
  ExpectMessage("name: \"t\"\nrobot { name: \"a\" tx_power_dbm: -11 }\n",
                "t.textproto:2:19: robot \"a\": tx_power_dbm -11 out of range [-10, 30]");
  ExpectMessage(
      "name: \"t\"\nradio { standard: STANDARD_80211G }\n"
      "robot { name: \"a\" rate_mbps: 5.5 }\nrobot { name: \"b\" rate_mbps: 7 }\n",
      "t.textproto:4:19: robot \"b\": rate_mbps 7 is not a rate of STANDARD_80211G"
      " (802.11a: 6 9 12 18 24 36 48 54; 802.11b: 1 2 5.5 11; 802.11g: both)");
}

}  // namespace
}  // namespace sitlnet
