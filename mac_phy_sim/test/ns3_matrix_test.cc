// The fast subset of the ns-3 side-by-side matrix: every row of
// docs/ns3_matrix.csv marked `fast` is run again here with the same cell,
// seeds and durations, and mac_phy_sim's mean throughput must stay within
// ns-3's pass rule (1.5 % saturation, 5 % hidden/exposed) of the ns-3 3.37
// mean recorded in the CSV. The CSV's provenance (ns-3 version, command
// line) is in its '#' lines; bench/ns3_reference/run.sh regenerates it.
// ns-3 itself is not run here: the whole matrix takes about half an hour of
// ns-3 time (docs/validation.md).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "mac_phy_sim/test/saturation_harness.h"
#include "mac_phy_sim/test/side_by_side_csv.h"

namespace sitlnet::mac::testing {
namespace {

std::vector<side_by_side::Row> FastRows() {
  const char* source = std::getenv("SITLNET_SOURCE_DIR");
  const std::string path = std::string(source ? source : ".") + "/docs/ns3_matrix.csv";
  std::vector<side_by_side::Row> rows;
  std::string error;
  EXPECT_TRUE(side_by_side::ReadCsv(path, &rows, &error)) << error;
  std::vector<side_by_side::Row> fast;
  for (const side_by_side::Row& row : rows) {
    if (row.c.fast) fast.push_back(row);
  }
  return fast;
}

TEST(Ns3MatrixTest, FastSubsetWithinNs3PassRule) {
  const std::vector<side_by_side::Row> rows = FastRows();
  ASSERT_GE(rows.size(), 10u);
  for (const side_by_side::Row& recorded : rows) {
    side_by_side::Row row = recorded;
    double sum = 0;
    for (int seed = 1; seed <= row.seeds; ++seed) {
      sum += RunCase(row.c, static_cast<uint64_t>(seed)).throughput_mbps;
    }
    row.ours_mean_mbps = sum / row.seeds;
    EXPECT_TRUE(side_by_side::Passes(row))
        << row.c.id << ": mac_phy_sim " << row.ours_mean_mbps << " Mb/s, ns-3 " << row.ns3_mean_mbps
        << " Mb/s (sd " << row.ns3_sd_mbps << "), error " << 100 * side_by_side::RelativeError(row)
        << " %, rule " << 100 * side_by_side::RuleFraction(row.c) << " %";
  }
}

}  // namespace
}  // namespace sitlnet::mac::testing
