// The side-by-side matrix as a CSV file (docs/ns3_matrix.csv): one row per
// cell with its parameters and the throughput means and spreads of ns-3 3.37
// and mac_phy_sim over the same seeds. Written by bench/ns3_reference, read
// by the fast subset in scripts/test and by the table generator. Lines
// starting with '#' are provenance comments.
#ifndef SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CSV_H_
#define SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CSV_H_

#include <string>
#include <vector>

#include "mac_phy_sim/test/side_by_side_case.h"

namespace sitlnet::side_by_side {

struct Row {
  Case c;
  int seeds = 0;
  double ns3_mean_mbps = 0, ns3_sd_mbps = 0;
  double ours_mean_mbps = 0, ours_sd_mbps = 0;
  double ns3_wall_s = 0, ours_wall_s = 0;  // Summed over the seeds.
};

std::string CsvHeader();
std::string FormatRow(const Row& row);
// Reads every row of `path`; false with *error naming file:line on a bad line.
bool ReadCsv(const std::string& path, std::vector<Row>* rows, std::string* error);

// ns-3's pass rule: 1.5 % on saturation means (its Bianchi validation), 5 %
// on hidden and exposed topologies and on the fading/shadowing links.
double RuleFraction(const Case& c);
double RelativeError(const Row& row);  // mac_phy_sim mean / ns-3 mean - 1.
bool Passes(const Row& row);

}  // namespace sitlnet::side_by_side

#endif  // SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CSV_H_
