#include "run_formats/run_formats.h"

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <fstream>
#include <sstream>

namespace sitlnet::run_formats {

std::string FormatPoseRow(const PoseRow& r) {
  // Degrees to 1e-8 (about a millimetre), like the metres beside them (0.1 mm).
  char line[384];
  std::snprintf(
      line, sizeof line, "%.3f,%d,%.4f,%.4f,%.4f,%.6f,%.6f,%.6f,%.6f,%.4f,%.4f,%.4f,%.8f,%.8f,%.4f",
      static_cast<double>(r.time_ns) / kNsPerS, r.robot, r.x_m, r.y_m, r.z_m, r.qw, r.qx, r.qy,
      r.qz, r.vx_m_s, r.vy_m_s, r.vz_m_s, r.latitude_deg, r.longitude_deg, r.altitude_m);
  return line;
}

void WriteConnectivityCsv(const std::string& path, const std::vector<ConnectivitySample>& samples,
                          int robots) {
  std::string header = "time_s,components";
  for (int i = 0; i < robots; ++i) header += ",robot_" + std::to_string(i);
  LineFile csv(path, header);
  for (const ConnectivitySample& sample : samples) {
    std::string row = std::to_string(static_cast<double>(sample.time_ns) / kNsPerS) + "," +
                      std::to_string(sample.components);
    for (int component : sample.component_of) row += "," + std::to_string(component);
    csv.Append(row);
  }
}

namespace {

// Corners of an obstacle's footprint, for gnuplot's polygon objects.
std::string ObstaclePolygon(const proto::Obstacle& box, int id) {
  const double yaw = box.yaw_deg() * M_PI / 180;
  const double hx = box.size_m().x() / 2, hy = box.size_m().y() / 2;
  const double corners[4][2] = {{-hx, -hy}, {hx, -hy}, {hx, hy}, {-hx, hy}};
  std::ostringstream text;
  text << "set object " << id << " polygon";
  for (int i = 0; i <= 4; ++i) {
    const double* c = corners[i % 4];
    const double x = box.center_m().x() + c[0] * std::cos(yaw) - c[1] * std::sin(yaw);
    const double y = box.center_m().y() + c[0] * std::sin(yaw) + c[1] * std::cos(yaw);
    text << (i == 0 ? " from " : " to ") << x << "," << y;
  }
  text << " fillstyle solid 0.35 fillcolor rgb 'gray40' behind\n";
  return text.str();
}

}  // namespace

std::vector<std::string> DrawPlots(const std::string& run_dir, const Scenario& scenario,
                                   const std::string& title, std::vector<std::string>* warnings) {
  const int robots = static_cast<int>(scenario.robots.size());
  std::ostringstream script;
  // Relative paths: gnuplot runs in the run folder (RunGnuplot), and so does a user who runs
  // plots.gnuplot again from there.
  script << "set datafile separator ','\n"
         << "set terminal pngcairo size 900,700 font 'sans,10'\n";
  // Top view.
  script << "set output 'trajectories.png'\nset title '" << title
         << ": trajectories (top view)'\nset xlabel 'x (m, east)'\nset ylabel 'y (m, north)'\n"
         << "set size ratio -1\nset key outside right\n";
  for (int i = 0; i < scenario.spec.obstacle_size(); ++i) {
    script << ObstaclePolygon(scenario.spec.obstacle(i), i + 1);
  }
  script << "plot for [i=0:" << robots - 1
         << "] 'trajectories.csv' every ::1 using ($2==i ? $3 : 1/0):4 with points pt 7 ps 0.35 "
            "title sprintf('robot %d', i)\n"
         << "unset object\nset size noratio\n";
  // Connectivity.
  script << "set output 'connectivity.png'\nset title '" << title
         << ": connected components of the communication graph'\n"
         << "set xlabel 'simulated time (s)'\nset ylabel 'components'\nset yrange [0:" << robots + 1
         << "]\nset ytics 1\nunset key\n"
         << "plot 'connectivity.csv' every ::1 using 1:2 with steps lw 2\n"
         << "set yrange [*:*]\nset ytics autofreq\n";
  // STF.
  script << "set output 'stf.png'\nset title '" << title
         << ": simulation-time factor per iteration (< 1: faster than real time)'\n"
         << "set xlabel 'simulated time (s)'\nset ylabel 'STF'\nset key\n"
         << "plot 'metrics.csv' every ::1 using ($2/1e9):7 with lines title 'STF', 1 with lines "
            "dt 2 title 'real time'\n";
  // A copy for the user (gnuplot itself reads the pipe); LineFile does not follow a link
  // planted at its path.
  try {
    LineFile copy(run_dir + "/plots.gnuplot", "", 1, "gnuplot script");
    copy.AppendRecord(script.str());
    copy.Flush();
  } catch (const Error& error) {
    warnings->push_back(error.what());
  }
  const std::string failure = RunGnuplot(script.str(), run_dir, run_dir + "/plots.log");
  if (!failure.empty()) {
    warnings->push_back(failure);
    return {};
  }
  return {run_dir + "/trajectories.png", run_dir + "/connectivity.png", run_dir + "/stf.png"};
}

}  // namespace sitlnet::run_formats
