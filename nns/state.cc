// The per-scenario state file: proof of ownership for `down`, robot lookup for
// `exec`. One line per fact, space separated, so that a human can read it.
#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <fstream>
#include <optional>
#include <sstream>

#include "nns/nns_internal.h"

namespace sitlnet::nns {

namespace {

// The source path is the one free-form field: a newline in it must not start a line of its
// own (a forged robot line would make `down` delete what it names). Control bytes and '%'
// are written as %XX.
std::string EscapePath(const std::string& path) {
  static const char* kHex = "0123456789ABCDEF";
  std::string out;
  for (const unsigned char c : path) {
    if (c < 0x20 || c == 0x7f || c == '%') {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    } else {
      out += static_cast<char>(c);
    }
  }
  return out;
}

std::optional<std::string> UnescapePath(const std::string& text) {
  std::string out;
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '%') {
      out += text[i];
      continue;
    }
    if (i + 2 >= text.size()) return std::nullopt;
    const std::string hex = text.substr(i + 1, 2);
    if (hex.size() != 2 || !std::isxdigit(static_cast<unsigned char>(hex[0])) ||
        !std::isxdigit(static_cast<unsigned char>(hex[1]))) {
      return std::nullopt;
    }
    out += static_cast<char>(std::stoi(hex, nullptr, 16));
    i += 2;
  }
  return out;
}

}  // namespace

std::string ScenarioState::PhysicsAddress(const OwnedRobot& robot) const {
  return FormatIpv4(robot.ctl_root_address) + ":" + std::to_string(physics_port);
}

ScenarioState StateFromScenario(const Scenario& scenario, const std::vector<int>& robots) {
  ScenarioState state;
  state.name = scenario.name;
  state.source_path = scenario.source_path;
  state.physics_port = static_cast<int>(scenario.spec.addresses().physics_port());
  for (const int index : scenario.RobotSlice(robots)) {
    const RobotPlan& plan = scenario.robots[index];
    state.robots.push_back(OwnedRobot{plan.index, plan.name, plan.netns, plan.root_veth,
                                      plan.wlan_address, plan.ctl_root_address,
                                      plan.ctl_robot_address});
  }
  return state;
}

std::string FormatState(const ScenarioState& state) {
  std::ostringstream out;
  out << "# sitlnet state, written by `sitlnet up` before it created anything (docs/nns.md)\n"
      << "scenario " << state.name << "\n"
      << "physics_port " << state.physics_port << "\n";
  for (const OwnedRobot& robot : state.robots) {
    out << "robot " << robot.index << " " << robot.name << " " << robot.netns << " "
        << robot.root_veth << " " << FormatIpv4(robot.wlan_address) << " "
        << FormatIpv4(robot.ctl_root_address) << " " << FormatIpv4(robot.ctl_robot_address) << "\n";
  }
  // Last: the path may contain spaces; it runs to the end of the line.
  out << "source " << EscapePath(state.source_path) << "\n";
  return out.str();
}

ScenarioState ParseState(const std::string& text, const std::string& source) {
  ScenarioState state;
  std::istringstream in(text);
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    std::string key;
    fields >> key;
    bool ok = true;
    if (key == "scenario") {
      // Once, before the robots: their names are checked against it (a second one would put
      // one scenario's robots under another's name, for `down` to remove).
      ok = state.name.empty() && state.robots.empty() && static_cast<bool>(fields >> state.name);
    } else if (key == "physics_port") {
      ok = static_cast<bool>(fields >> state.physics_port);
    } else if (key == "source") {
      const std::optional<std::string> path = UnescapePath(line.size() > 7 ? line.substr(7) : "");
      ok = path.has_value();
      if (ok) state.source_path = *path;
    } else if (key == "robot") {
      OwnedRobot robot;
      std::string wlan, ctl_root, ctl_robot;
      ok = static_cast<bool>(fields >> robot.index >> robot.name >> robot.netns >>
                             robot.root_veth >> wlan >> ctl_root >> ctl_robot);
      const auto a = ParseIpv4(wlan), b = ParseIpv4(ctl_root), c = ParseIpv4(ctl_robot);
      ok = ok && a && b && c;
      // Names follow the plan's rule: `down` deletes a namespace and a link by these names, so
      // a line naming anything else (another scenario's robot, docker0) is refused.
      ok = ok && !state.name.empty() && robot.index >= 0 && robot.index < kMaxRobots &&
           robot.netns == RobotNetnsName(state.name, robot.name) &&
           robot.root_veth == RobotRootVethName(state.name, robot.index);
      if (ok) {
        robot.wlan_address = *a;
        robot.ctl_root_address = *b;
        robot.ctl_robot_address = *c;
        state.robots.push_back(std::move(robot));
      }
    } else {
      ok = false;
    }
    // Nothing after a line's fields (the source path takes the rest of its line).
    if (std::string extra; ok && key != "source" && fields >> extra) ok = false;
    if (!ok) {
      throw Error(source + ":" + std::to_string(line_number) + ": malformed state line \"" + line +
                  "\"");
    }
  }
  if (state.name.empty()) throw Error(source + ": state file names no scenario");
  return state;
}

namespace internal {

uint32_t LinkGroupForScenario(const std::string& scenario) {
  // FNV-1a of the name in the low 24 bits, under a fixed high byte (0x51, 'Q'
  // for no reason but rarity): groups are per namespace and nearly always 0,
  // and Down checks the group's members by name before deleting it.
  uint32_t hash = 2166136261u;
  for (unsigned char c : scenario) hash = (hash ^ c) * 16777619u;
  return 0x51000000u | (hash & 0x00ffffffu);
}

std::string StatePath(const std::string& scenario) {
  return std::string(kStateDir) + "/" + scenario + "/state";
}

namespace {

void MakeDirectory(const std::string& dir) {
  if (mkdir(dir.c_str(), 0755) != 0 && errno != EEXIST) {
    throw Error(SystemErrorMessage("create state directory \"" + dir + "\"", errno));
  }
}

}  // namespace

StateLock::StateLock() {
  MakeDirectory(kStateDir);
  const std::string path = std::string(kStateDir) + "/.lock";
  fd_.Reset(open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644));
  if (!fd_.valid()) throw Error(SystemErrorMessage("open \"" + path + "\"", errno));
  while (flock(fd_.get(), LOCK_EX) != 0) {
    if (errno != EINTR) throw Error(SystemErrorMessage("lock \"" + path + "\"", errno));
  }
}

void WriteState(const ScenarioState& state) {
  MakeDirectory(kStateDir);
  MakeDirectory(std::string(kStateDir) + "/" + state.name);
  const std::string path = StatePath(state.name);
  const std::string temporary = path + ".tmp";
  const std::string text = FormatState(state);
  const int fd = open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) throw Error(SystemErrorMessage("write \"" + temporary + "\"", errno));
  const bool written = write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size());
  const int err = errno;
  close(fd);
  // rename is atomic: a reader sees the whole state or none (kill -9 safe).
  if (!written || rename(temporary.c_str(), path.c_str()) != 0) {
    unlink(temporary.c_str());
    throw Error(SystemErrorMessage("write \"" + path + "\"", written ? errno : err));
  }
}

void RemoveState(const std::string& scenario) {
  const std::string dir = std::string(kStateDir) + "/" + scenario;
  unlink(StatePath(scenario).c_str());
  unlink((StatePath(scenario) + ".tmp").c_str());
  // What daemons leave behind after a crash: their pid files and sockets.
  for (const char* file : {"medium.pid", "physics.pid", "run.pid", "medium.sock"}) {
    unlink((dir + "/" + file).c_str());
  }
  if (rmdir(dir.c_str()) != 0 && errno != ENOENT) {
    throw Error(SystemErrorMessage("remove state directory \"" + dir + "\"", errno));
  }
}

}  // namespace internal

std::vector<std::string> ListScenarios() {
  std::vector<std::string> names;
  DIR* dir = opendir(kStateDir);
  if (dir == nullptr) return names;
  while (dirent* entry = readdir(dir)) {
    const std::string name = entry->d_name;
    if (name == "." || name == "..") continue;
    if (access(internal::StatePath(name).c_str(), F_OK) == 0) names.push_back(name);
  }
  closedir(dir);
  std::sort(names.begin(), names.end());
  return names;
}

std::optional<ScenarioState> ReadScenarioState(const std::string& name) {
  const std::string path = internal::StatePath(name);
  std::ifstream file(path);
  if (!file) return std::nullopt;
  std::ostringstream text;
  text << file.rdbuf();
  ScenarioState state = ParseState(text.str(), path);
  if (state.name != name) {
    throw Error(path + ": state file names scenario \"" + state.name + "\", not \"" + name + "\"");
  }
  return state;
}

RobotRef ResolveRobot(const std::vector<ScenarioState>& scenarios, const std::string& robot,
                      const std::string& scenario_name) {
  std::vector<RobotRef> matches;
  for (const ScenarioState& scenario : scenarios) {
    if (!scenario_name.empty() && scenario.name != scenario_name) continue;
    for (const OwnedRobot& candidate : scenario.robots) {
      // "<robot>" or its namespace name "<scenario>-<robot>".
      if (candidate.name == robot || (scenario_name.empty() && candidate.netns == robot)) {
        matches.push_back(RobotRef{scenario, candidate});
      }
    }
  }
  if (matches.size() == 1) return matches[0];
  if (matches.empty()) {
    if (!scenario_name.empty() &&
        std::none_of(scenarios.begin(), scenarios.end(),
                     [&](const ScenarioState& s) { return s.name == scenario_name; })) {
      throw Error("scenario \"" + scenario_name + "\" is not up");
    }
    throw Error("no robot \"" + robot + "\" in " +
                (scenario_name.empty() ? std::string("any scenario that is up")
                                       : "scenario \"" + scenario_name + "\""));
  }
  std::string candidates;
  for (const RobotRef& match : matches) {
    candidates.append(candidates.empty() ? "" : ", ").append(match.robot.netns);
  }
  throw Error("robot \"" + robot + "\" is ambiguous: " + candidates +
              "; name it as <scenario>-<robot> or use --scenario");
}

}  // namespace sitlnet::nns
