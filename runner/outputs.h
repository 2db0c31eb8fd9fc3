// The files of a run folder (docs/run.md): trajectories.csv, deliveries.csv,
// connectivity.csv, summary.json, and the PNG plots drawn by gnuplot.
#ifndef SITLNET_RUNNER_OUTPUTS_H_
#define SITLNET_RUNNER_OUTPUTS_H_

#include <cstdio>
#include <string>
#include <vector>

#include "common/common.h"
#include "runner/connectivity.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

// One robot's pose sample for trajectories.csv.
struct PoseRow {
  TimeNs time_ns = 0;
  int robot = 0;
  double x_m = 0, y_m = 0, z_m = 0;
  double qw = 1, qx = 0, qy = 0, qz = 0;
  double vx_m_s = 0, vy_m_s = 0, vz_m_s = 0;
  // The position on Earth (the scenario's geodetic_origin): WGS-84, altitude above sea level.
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;
};
inline constexpr char kTrajectoryHeader[] =
    "time_s,robot,x_m,y_m,z_m,qw,qx,qy,qz,vx_m_s,vy_m_s,vz_m_s,latitude_deg,longitude_deg,"
    "altitude_m";
std::string FormatPoseRow(const PoseRow& row);

inline constexpr char kDeliveryHeader[] = "time_ns,from,to,rx_power_dbm,sinr_db";

// Writes connectivity.csv: time_s,components,robot_0,...,robot_{n-1} (each
// robot's component id).
void WriteConnectivityCsv(const std::string& path, const std::vector<ConnectivitySample>& samples,
                          int robots);

// Draws trajectories.png (top view over the obstacles), connectivity.png and
// stf.png into `run_dir` with gnuplot. Returns the PNGs written; a missing
// gnuplot or a failed plot is a warning line in *warnings, not an error.
std::vector<std::string> DrawPlots(const std::string& run_dir, const Scenario& scenario,
                                   const std::string& title, std::vector<std::string>* warnings);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_OUTPUTS_H_
