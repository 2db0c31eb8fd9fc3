#include "tests/integration/run_test_util.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace sitlnet::nns::testing {

RunScenario WriteScenario(int slot, const std::string& robots, const std::string& extra,
                          const std::string& address_fields) {
  const unsigned pid = static_cast<unsigned>(getpid());
  RunScenario s;
  s.name = "ru" + std::to_string(pid % 10000) + std::to_string(slot);
  const std::string third = std::to_string(pid % 250);
  s.path = TempDir() + "/" + s.name + ".textproto";
  std::ofstream(s.path) << "name: \"" << s.name << "\"\n"
                        << robots << "addresses { wlan_subnet: \"10." << 240 + slot << "." << third
                        << ".0/24\" ctl_subnet: \"10." << 220 + slot << "." << third << ".0/24\" "
                        << address_fields << " }\n"
                        << extra;
  return s;
}

std::string WlanPrefix(int slot) {
  return "10." + std::to_string(240 + slot) + "." + std::to_string(getpid() % 250) + ".";
}

std::string RelayFleetRobots(int slot) {
  const std::string station = WlanPrefix(slot) + "1";
  return "robot { name: \"gcs\" position_m { x: 0 y: -10 z: 2 } ground_station: true }\n"
         "robot { name: \"ap\" position_m { x: 0 y: 0 z: 0.2 } image: \"test_autopilot\" "
         "ardupilot_json_port: 9002 args: [\"--json-port\", \"9002\", \"--telemetry\", \"" +
         station + ":14550\"] }\n" +
         "robot { name: \"px\" position_m { x: 5 y: 0 z: 0.2 } image: \"test_autopilot\" "
         "px4_sim_port: 4560 args: [\"--px4-port\", \"4560\", \"--telemetry\", \"" +
         station + ":14550\"] }\n";
}

CommandResult SitlnetRun(const RunScenario& scenario, const std::string& out,
                         std::vector<std::string> extra_args) {
  std::vector<std::string> argv = {SitlnetBinary(), "run", scenario.path,
                                   "--out",         out,   "--no-progress"};
  argv.insert(argv.end(), extra_args.begin(), extra_args.end());
  return RunCommand(argv, 300 * kNsPerS);
}

double SummaryNumber(const std::string& summary, const std::string& after, const std::string& key) {
  const size_t from = summary.find(after);
  const size_t at = from == std::string::npos ? from : summary.find(key, from);
  if (at == std::string::npos) return std::nan("");
  return std::strtod(summary.c_str() + at + key.size(), nullptr);
}

CommandResult SitlnetRunUntil(const RunScenario& scenario, const std::string& out,
                              const std::function<bool()>& done, TimeNs timeout_ns) {
  integration_test::Child run(
      {SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  integration_test::WaitForFiles(
      out + "/robots", [&] { return run.Poll() >= 0 || done(); }, timeout_ns);
  if (run.Poll() < 0) kill(run.pid(), SIGINT);
  const int exit_code = run.Wait(60 * kNsPerS);
  return {exit_code, run.out(), run.err()};
}

void ExpectNothingLeft(const std::string& name) {
  EXPECT_FALSE(StateExists(name)) << name;
  const std::vector<std::string> up = ListScenarios();
  EXPECT_EQ(std::find(up.begin(), up.end(), name), up.end()) << name;
  for (const char* robot : {"a", "b"}) {
    EXPECT_FALSE(NetnsExists(name + "-" + robot)) << name << "-" << robot;
  }
  EXPECT_FALSE(NetnsExists(CtlNetnsName(name))) << name;  // The root sides went with it.
  // No cgroup folder of the scenario in any hierarchy (/sys/fs/cgroup itself for cgroup v2 alone,
  // or its subfolders: unified, memory, pids, ...).
  std::error_code error;
  std::vector<std::filesystem::path> mounts = {"/sys/fs/cgroup"};
  for (const auto& entry : std::filesystem::directory_iterator("/sys/fs/cgroup", error)) {
    if (entry.is_directory(error)) mounts.push_back(entry.path());
  }
  for (const std::filesystem::path& mount : mounts) {
    EXPECT_FALSE(std::filesystem::exists(mount / "sitlnet" / name, error))
        << mount / "sitlnet" / name;
  }
}

std::vector<double> CapturedTimes(const std::string& out, const std::string& filter,
                                  std::vector<int>* udp_lengths,
                                  std::vector<std::string>* sources) {
  const CommandResult tshark = RunCommand(
      {"tshark", "-r", out + "/medium.pcap", "-Y", "(" + filter + ") && wlan.fc.retry == 0", "-T",
       "fields", "-e", "frame.time_epoch", "-e", "udp.length", "-e", "ipv6.src"},
      60 * kNsPerS);
  EXPECT_EQ(tshark.exit_code, 0) << tshark.err;
  std::vector<double> times;
  std::istringstream lines(tshark.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    double time = 0;
    int length = 0;
    std::string source;
    fields >> time >> length >> source;
    times.push_back(time);
    if (udp_lengths != nullptr) udp_lengths->push_back(length);
    if (sources != nullptr) sources->push_back(source);
  }
  return times;
}

std::vector<TrajectoryRow> TrajectoryRows(const std::string& csv, int robot) {
  std::vector<TrajectoryRow> rows;
  std::istringstream lines(csv);
  for (std::string line; std::getline(lines, line);) {
    TrajectoryRow row;
    int r = -1;
    if (std::sscanf(line.c_str(), "%lf,%d,%lf,%lf,%lf", &row.t_s, &r, &row.x_m, &row.y_m,
                    &row.z_m) == 5 &&
        r == robot) {
      rows.push_back(row);
    }
  }
  return rows;
}

HostGcs::HostGcs(const std::string& script, const std::vector<std::string>& args,
                 const std::string& output) {
  std::vector<std::string> argv = {"sh", "-c",
                                   "out=$1; shift; exec node \"$0\" \"$@\" > \"$out\" 2>&1",
                                   NodeMavlinkDir() + "/" + script, output};
  argv.insert(argv.end(), args.begin(), args.end());
  gcs_.emplace(argv);
  int port = 0;
  if (integration_test::WaitForFiles(
          std::filesystem::path(output).parent_path(),
          [&] {
            return std::sscanf(ReadAll(output).c_str(), "LISTENING on UDP port %d", &port) == 1;
          },
          30 * kNsPerS)) {
    port_ = port;
  }
}

int FreePort(int type) {
  const int probe = socket(AF_INET, type | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t size = sizeof address;
  const bool bound =
      bind(probe, reinterpret_cast<const sockaddr*>(&address), sizeof address) == 0 &&
      getsockname(probe, reinterpret_cast<sockaddr*>(&address), &size) == 0;
  close(probe);
  return bound ? ntohs(address.sin_port) : 0;
}

int StartHostGcs(std::optional<integration_test::Child>* gcs,
                 const std::vector<std::string>& args) {
  std::vector<std::string> argv = {"node", NodeMavlinkDir() + "/host_gcs.cjs"};
  argv.insert(argv.end(), args.begin(), args.end());
  gcs->emplace(argv);
  if (!(*gcs)->WaitForOutput(false, "LISTENING on UDP port", 30 * kNsPerS)) return 0;
  int port = 0;
  const std::string& out = (*gcs)->out();
  std::sscanf(out.c_str() + out.find("LISTENING"), "LISTENING on UDP port %d", &port);
  return port;
}

std::map<int, int> FirstHeartbeatMs(const std::string& gcs_output) {
  std::map<int, int> first;
  std::istringstream lines(gcs_output);
  for (std::string line; std::getline(lines, line);) {
    int sysid = 0, msgid = -1, wall_ms = 0;
    char name[64];
    if (std::sscanf(line.c_str(), "HEARD sysid=%d msgid=%d name=%63s wall_ms=%d", &sysid, &msgid,
                    name, &wall_ms) == 4 &&
        msgid == 0 && !first.count(sysid)) {
      first[sysid] = wall_ms;
    }
  }
  return first;
}

std::map<int, int> FirstHeartbeatClockMs(const std::string& gcs_output) {
  std::map<int, int> first;
  int64_t first_boot_ms = -1, latest_boot_ms = -1;
  std::istringstream lines(gcs_output);
  for (std::string line; std::getline(lines, line);) {
    int sysid = 0, msgid = -1;
    if (std::sscanf(line.c_str(), "HEARD sysid=%d msgid=%d", &sysid, &msgid) != 2) continue;
    const size_t boot = line.find(" boot_ms=");
    if (boot != std::string::npos) {
      const int64_t boot_ms = std::strtoll(line.c_str() + boot + 9, nullptr, 10);
      if (first_boot_ms < 0) first_boot_ms = boot_ms;
      latest_boot_ms = std::max(latest_boot_ms, boot_ms);
    }
    if (msgid == 0 && !first.count(sysid)) {
      first[sysid] = first_boot_ms < 0 ? 0 : static_cast<int>(latest_boot_ms - first_boot_ms);
    }
  }
  return first;
}

// A ground station's robot image: `script` of tests/node_mavlink with `args`, run by node, the
// folder (and its node_modules) bound in. Ready once bound (lockstep_station.cjs).
std::string WriteStationImage(const std::string& script, const std::vector<std::string>& args) {
  const std::string path = TempDir() + "/" + script + ".textproto";
  const std::string folder = integration_test::SourceDir() + "/tests/node_mavlink";
  std::ofstream image(path);
  image << "name: \"" << script << "\"\ncommand: \"/usr/bin/env\"\ncommand: \"node\"\n"
        << "command: \"" << folder << "/" << script << "\"\n";
  for (const std::string& arg : args) image << "command: \"" << arg << "\"\n";
  image << "files: \"" << folder << "\"\nready_log_line: \"GCS ready\"\n";
  return path;
}

std::string NodeMavlinkDir() { return integration_test::SourceDir() + "/tests/node_mavlink"; }

namespace {

// Why $`variable` names no autopilot build holding `program`, or "" if it does; `how` says
// where docs/autopilots.md tells how to make one.
std::string AutopilotBuildMissing(const char* variable, const char* program, const char* how) {
  const char* dir = std::getenv(variable);
  if (dir == nullptr || *dir == '\0') return std::string(variable) + " is not set: " + how;
  if (!std::filesystem::exists(std::string(dir) + "/" + program)) {
    return std::string(variable) + "=" + dir + " holds no " + program + ": " + how;
  }
  return "";
}

}  // namespace

std::string ArduPilotMissing() {
  return AutopilotBuildMissing("SITLNET_ARDUPILOT_DIR", "bin/arducopter",
                               "build ArduCopter SITL as docs/autopilots.md says and point it at "
                               "the folder (bin/arducopter, params/copter.parm)");
}

std::string Px4Missing() {
  return AutopilotBuildMissing("SITLNET_PX4_DIR", "bin/px4",
                               "point it at a PX4 v1.14 px4_sitl_default build folder (bin/px4, "
                               "etc/), docs/autopilots.md \"Building PX4\"");
}

bool LeanAutopilots() {
  const char* profile = std::getenv("SITLNET_TEST_AUTOPILOT_PROFILE");
  return profile != nullptr && std::string(profile) == "lean";
}

std::string NodeMavlinkMissing() {
  if (std::system("node --version >/dev/null 2>&1") != 0) return "node is not installed";
  if (!std::filesystem::exists(NodeMavlinkDir() + "/node_modules/node-mavlink/package.json")) {
    return "node-mavlink is not installed in " + NodeMavlinkDir() +
           "/node_modules (scripts/setup installs it)";
  }
  return "";
}

}  // namespace sitlnet::nns::testing
