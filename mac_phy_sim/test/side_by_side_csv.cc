#include "mac_phy_sim/test/side_by_side_csv.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace sitlnet::side_by_side {
namespace {

constexpr const char* kColumns =
    "id,standard,short_slot,rate_mbps,senders,topology,payload_bytes,rts_threshold_bytes,capture,"
    "near_m,far_m,nakagami_m,lognormal_sigma_db,rate_control,table_error_model,warmup_s,measure_s,"
    "unlimited_retries,path_loss,"
    "fast,seeds,"
    "ns3_mean_mbps,ns3_sd_mbps,"
    "ours_mean_mbps,ours_sd_mbps,ns3_wall_s,ours_wall_s";
// Rows of n/ac cells carry three more columns (a/b/g rows keep the 27 above).
constexpr const char* kHtColumns = ",mcs,channel_width_mhz,short_gi";
constexpr size_t kColumnCount = 27;
// EDCA rows carry three more after those (side_by_side_case.h).
constexpr const char* kEdcaColumns = ",qos,high_priority,measured_priority";

bool ParseStandard(const std::string& s, Standard* out) {
  for (Standard standard : {Standard::kA, Standard::kB, Standard::kG, Standard::kN24,
                            Standard::kN5, Standard::kAc}) {
    if (s == StandardName(standard)) {
      *out = standard;
      return true;
    }
  }
  return false;
}

bool ParseTopology(const std::string& s, Topology* out) {
  for (Topology t :
       {Topology::kRing, Topology::kSink, Topology::kHidden, Topology::kExposed, Topology::kLink}) {
    if (s == TopologyName(t)) {
      *out = t;
      return true;
    }
  }
  return false;
}

bool ParsePathLoss(std::string s, Case* c) {
  PathLoss* out = &c->path_loss;
  // A "-update<N>ms" suffix: the condition model's update period (CellPathLossName).
  const size_t update = s.rfind("-update");
  if (update != std::string::npos && s.size() > update + 9 &&
      s.compare(s.size() - 2, 2, "ms") == 0) {
    const std::string digits = s.substr(update + 7, s.size() - update - 9);
    if (digits.empty() || digits.find_first_not_of("0123456789") != std::string::npos) return false;
    c->v2v_update_period_ms = std::stoi(digits);
    s.resize(update);
  }
  for (PathLoss p :
       {PathLoss::kLogDistance, PathLoss::kTwoRayGround, PathLoss::kV2vUrban, PathLoss::kV2vHighway,
        PathLoss::kV2vUrbanNoShadowing, PathLoss::kV2vHighwayNoShadowing}) {
    if (s == PathLossName(p)) {
      *out = p;
      return true;
    }
  }
  return false;
}

bool ParseLine(const std::string& line, Row* row) {
  std::vector<std::string> f;
  std::stringstream in(line);
  for (std::string cell; std::getline(in, cell, ',');) f.push_back(cell);
  try {
    Case& c = row->c;
    c.id = f[0];
    c.ampdu = IsAmpduId(c.id);
    if (f.size() < 2 || !ParseStandard(f[1], &c.standard)) return false;
    const size_t base = kColumnCount + (IsHtOrVht(c.standard) ? 3 : 0);
    if (f.size() != base && f.size() != base + 3) return false;
    if (f.size() == base + 3) {
      c.qos = f[base] == "1";
      c.high_priority = std::stoi(f[base + 1]);
      c.measured_priority = std::stoi(f[base + 2]);
    }
    if (!ParseTopology(f[5], &c.topology)) return false;
    c.short_slot = f[2] == "1";
    c.rate_mbps = std::stod(f[3]);
    c.senders = std::stoi(f[4]);
    c.payload_bytes = std::stoi(f[6]);
    c.rts_threshold_bytes = static_cast<uint32_t>(std::stoul(f[7]));
    c.capture = f[8] == "1";
    c.near_m = std::stod(f[9]);
    c.far_m = std::stod(f[10]);
    c.nakagami_m = std::stod(f[11]);
    c.lognormal_sigma_db = std::stod(f[12]);
    const int rate_control = std::stoi(f[13]);
    if (rate_control < 0 || rate_control > 2) return false;
    c.rate_control = static_cast<RateControl>(rate_control);
    c.table_error_model = f[14] == "1";
    c.warmup_s = std::stod(f[15]);
    c.measure_s = std::stod(f[16]);
    c.unlimited_retries = f[17] == "1";
    if (!ParsePathLoss(f[18], &c)) return false;
    c.fast = f[19] == "1";
    row->seeds = std::stoi(f[20]);
    row->ns3_mean_mbps = std::stod(f[21]);
    row->ns3_sd_mbps = std::stod(f[22]);
    row->ours_mean_mbps = std::stod(f[23]);
    row->ours_sd_mbps = std::stod(f[24]);
    row->ns3_wall_s = std::stod(f[25]);
    row->ours_wall_s = std::stod(f[26]);
    if (IsHtOrVht(c.standard)) {
      c.mcs = std::stoi(f[27]);
      c.channel_width_mhz = std::stoi(f[28]);
      c.short_gi = f[29] == "1";
    }
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

}  // namespace

std::string CsvHeader() { return kColumns; }

std::string FormatRow(const Row& r) {
  const Case& c = r.c;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s,%s,%d,%g,%d,%s,%d,%u,%d,%g,%g,%g,%g,%d,%d,%g,%g,%d,%s,"
                "%d,%d,%.6f,%.6f,%.6f,%.6f,%.3f,%.3f",
                c.id.c_str(), StandardName(c.standard), c.short_slot ? 1 : 0, c.rate_mbps,
                c.senders, TopologyName(c.topology), c.payload_bytes, c.rts_threshold_bytes,
                c.capture ? 1 : 0, c.near_m, c.far_m, c.nakagami_m, c.lognormal_sigma_db,
                static_cast<int>(c.rate_control), c.table_error_model ? 1 : 0, c.warmup_s, c.measure_s,
                c.unlimited_retries ? 1 : 0, CellPathLossName(c).c_str(), c.fast ? 1 : 0, r.seeds,
                r.ns3_mean_mbps, r.ns3_sd_mbps, r.ours_mean_mbps, r.ours_sd_mbps, r.ns3_wall_s,
                r.ours_wall_s);
  std::string line = buf;
  if (IsHtOrVht(c.standard)) {
    line += "," + std::to_string(c.mcs) + "," + std::to_string(c.channel_width_mhz) + "," +
            (c.short_gi ? "1" : "0");
  }
  if (IsEdcaCell(c)) {
    line += std::string(",") + (c.qos ? "1" : "0") + "," + std::to_string(c.high_priority) + "," +
            std::to_string(c.measured_priority);
  }
  return line;
}

bool ReadCsv(const std::string& path, std::vector<Row>* rows, std::string* error) {
  std::ifstream in(path);
  if (!in) {
    *error = path + ": cannot open";
    return false;
  }
  int line_number = 0;
  for (std::string line; std::getline(in, line);) {
    ++line_number;
    if (line.empty() || line[0] == '#' || line == kColumns) continue;
    Row row;
    if (!ParseLine(line, &row)) {
      *error = path + ":" + std::to_string(line_number) + ": not a row of " + kColumns +
               " (n/ac rows: then" + kHtColumns + "; EDCA rows: then" + kEdcaColumns + ")";
      return false;
    }
    rows->push_back(row);
  }
  return true;
}

double RuleFraction(const Case& c) {
  return c.topology == Topology::kRing || c.topology == Topology::kSink ? 0.015 : 0.05;
}

double RelativeError(const Row& r) { return r.ours_mean_mbps / r.ns3_mean_mbps - 1; }

bool Passes(const Row& r) { return std::fabs(RelativeError(r)) <= RuleFraction(r.c); }

}  // namespace sitlnet::side_by_side
