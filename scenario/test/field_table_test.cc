// docs/scenario.md's generated blocks (field_table.h): a row per field from the options, and
// blocks that are malformed refused rather than half written.
#include "scenario/field_table.h"

#include <gtest/gtest.h>

#include <string>

#include "common/common.h"
#include "sitlnet/scenario.pb.h"

namespace sitlnet {
namespace {

TEST(FieldTableTest, RowsComeFromTheOptions) {
  const std::string table = FieldTable(proto::Radio::descriptor());
  EXPECT_NE(table.find("| `tx_power_dbm` | dBm | 16.0206 | [-10, 30]; ns-3's default |\n"),
            std::string::npos)
      << table;
  EXPECT_NE(table.find("| `capture_margin_db` | dB | unset: no capture | [0, 100]; "),
            std::string::npos)
      << table;
  // The steps take the iteration's bounds and unit (same_rules_as), with their own help.
  EXPECT_NE(FieldTable(proto::Timing::descriptor())
                .find("| `physics_step_us` | µs | 1000 | > 0, at most 60000000; divides "
                      "`iteration_us` |\n"),
            std::string::npos);
}

TEST(FieldTableTest, ReplacesOnlyTheBlocks) {
  const std::string page =
      "intro\n<!-- scenario-doc: Lidar -->\nold\n<!-- scenario-doc end -->\nrest\n";
  EXPECT_EQ(WithFieldTables(page), "intro\n<!-- scenario-doc: Lidar -->\n" +
                                       FieldTable(proto::Lidar::descriptor()) +
                                       "<!-- scenario-doc end -->\nrest\n");
  EXPECT_EQ(WithFieldTables(WithFieldTables(page)), WithFieldTables(page));
  EXPECT_THROW(WithFieldTables("<!-- scenario-doc: Nope -->\n<!-- scenario-doc end -->\n"), Error);
  EXPECT_THROW(WithFieldTables("<!-- scenario-doc: Lidar -->\nno end\n"), Error);
}

}  // namespace
}  // namespace sitlnet
