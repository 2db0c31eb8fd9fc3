#include "tests/integration/mavlink_oracle.h"

#include <cstdio>
#include <fstream>
#include <sstream>

namespace sitlnet::nns::testing {

namespace {

int CountOf(const std::map<std::string, int>& counts, const std::string& key) {
  const auto it = counts.find(key);
  return it == counts.end() ? 0 : it->second;
}

}  // namespace

int Crossed::Messages(const std::string& name) const { return CountOf(messages, name); }

int Crossed::Commands(int id) const { return CountOf(commands, std::to_string(id)); }

int Crossed::CommandsTo(int target, int id) const {
  const auto it = commands_to.find({std::to_string(target), std::to_string(id)});
  return it == commands_to.end() ? 0 : it->second;
}

Crossed DecodeMavlink(const std::string& bytes, const std::string& file) {
  std::ofstream(file, std::ios::binary) << bytes;
  const CommandResult node = RunCommand(
      {"sh", "-c", "node \"$0/decode.cjs\" < \"$1\"", NodeMavlinkDir(), file}, 120 * kNsPerS);
  EXPECT_EQ(node.exit_code, 0) << node.err;
  Crossed crossed;
  std::istringstream decoded(node.out);
  for (std::string line; std::getline(decoded, line);) {
    std::istringstream words(line);
    std::string kind, id, name;
    words >> kind >> id >> name;
    if (kind == "COUNTS") crossed.counts = line;
    if (kind != "MSG") continue;
    ++crossed.messages[name];
    std::string command, target;
    for (std::string word; words >> word;) {
      if (word.rfind("sysid=", 0) == 0) ++crossed.systems[word.substr(6)];
      if (word.rfind("command=", 0) == 0) command = word.substr(8);
      if (word.rfind("target_system=", 0) == 0) target = word.substr(14);
    }
    if (name == "COMMAND_LONG") {
      ++crossed.commands[command];
      ++crossed.commands_to[{target, command}];
    }
  }
  return crossed;
}

std::map<std::string, std::string> UdpPayloads(const std::string& out, const std::string& prefilter,
                                               const std::string& filter,
                                               const std::string& key_field) {
  const std::string kept = out + "/prefiltered.pcap";
  const CommandResult tcpdump =
      RunCommand({"tcpdump", "-r", out + "/medium.pcap", "-w", kept, prefilter}, 120 * kNsPerS);
  EXPECT_EQ(tcpdump.exit_code, 0) << tcpdump.err;
  const CommandResult tshark = RunCommand(
      {"tshark", "-r", kept, "-Y", "udp && (" + filter + ") && wlan.fc.retry == 0 && !icmp", "-T",
       "fields", "-e", key_field, "-e", "data.data"},
      120 * kNsPerS);
  std::remove(kept.c_str());
  EXPECT_EQ(tshark.exit_code, 0) << tshark.err;
  std::map<std::string, std::string> payloads;
  std::istringstream lines(tshark.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string key, hex;
    fields >> key >> hex;
    std::string& bytes = payloads[key];
    for (size_t i = 0; i + 1 < hex.size(); i += 2) {
      bytes.push_back(static_cast<char>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    }
  }
  return payloads;
}

std::map<std::string, FlightEvent> FlightEvents(const std::string& log, const std::string& prefix) {
  std::map<std::string, FlightEvent> events;
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind(prefix, 0) != 0) continue;
    const char* text = line.c_str() + prefix.size();
    char name[32];
    double t = 0, since = -1;
    if (std::sscanf(text, "EVENT %31s t_ms=%lf since_ms=%lf", name, &t, &since) >= 2) {
      events[name] = {t / 1000, since < 0 ? t / 1000 : since / 1000};
    } else if (std::sscanf(text, "%31[A-Z_] t=%lf", name, &t) == 2) {
      events[name] = {t, t};
    }
  }
  return events;
}

const TrajectoryRow& RowAt(const std::vector<TrajectoryRow>& rows, double t_s) {
  size_t i = 0;
  while (i + 1 < rows.size() && rows[i + 1].t_s <= t_s + 1e-9) ++i;
  return rows.at(i);
}

}  // namespace sitlnet::nns::testing
