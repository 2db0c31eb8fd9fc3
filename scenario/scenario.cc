// Loading: text -> proto spec (with source locations) -> validated Scenario.
#include "scenario/scenario.h"

#include <google/protobuf/io/tokenizer.h>
#include <google/protobuf/text_format.h>

#include <fstream>
#include <sstream>

#include "scenario/source_locator.h"
#include "scenario/validation.h"

namespace sitlnet {
namespace {

using scenario_internal::SourceLocator;

// Collects the first protobuf parse error as "source:line:col: message".
class FirstErrorCollector : public google::protobuf::io::ErrorCollector {
 public:
  explicit FirstErrorCollector(std::string source_name) : source_name_(std::move(source_name)) {}
  void AddError(int line, int column, const std::string& message) override {
    if (!first_.empty()) return;
    first_ = source_name_ + ":" + std::to_string(line + 1) + ":" + std::to_string(column + 1) +
             ": " + message;
  }
  const std::string& first() const { return first_; }

 private:
  std::string source_name_;
  std::string first_;
};

}  // namespace

std::string RobotNetnsName(const std::string& scenario, const std::string& robot) {
  return scenario + "-" + robot;
}

std::string RobotRootVethName(const std::string& scenario, int index) {
  return scenario + "-c" + std::to_string(index);
}

int Scenario::RobotIndex(std::string_view robot_name) const {
  for (const RobotPlan& robot : robots) {
    if (robot.name == robot_name) return robot.index;
  }
  return -1;
}

int Scenario::NodeIndex(std::string_view node_name) const {
  for (size_t i = 0; i < nodes.size(); ++i) {
    if (nodes[i].name == node_name) return static_cast<int>(i);
  }
  return -1;
}

std::vector<int> Scenario::RobotSlice(const std::vector<int>& requested) const {
  const int count = static_cast<int>(robots.size());
  std::vector<int> slice;
  if (requested.empty()) {
    for (int i = 0; i < count; ++i) slice.push_back(i);
    return slice;
  }
  for (int robot : requested) {
    if (robot < 0 || robot >= count || (!slice.empty() && robot <= slice.back())) {
      throw Error(source_path + ": robot index " + std::to_string(robot) +
                  " in a slice of robots: a slice holds ascending indices below " +
                  std::to_string(count));
    }
    slice.push_back(robot);
  }
  return slice;
}

void ParseTextProtoOrThrow(std::string_view text, const std::string& source_name,
                           google::protobuf::Message* message,
                           google::protobuf::TextFormat::ParseInfoTree* locations) {
  FirstErrorCollector errors(source_name);
  google::protobuf::TextFormat::Parser parser;
  parser.RecordErrorsTo(&errors);
  if (locations != nullptr) parser.WriteLocationsTo(locations);
  if (!parser.ParseFromString(std::string(text), message)) {
    throw Error(errors.first().empty() ? source_name + ": cannot parse" : errors.first());
  }
}

std::string ReadFileOrThrow(const std::string& path, const std::string& what) {
  std::ifstream file(path);
  if (!file) throw Error(SystemErrorMessage("open " + what + " \"" + path + "\"", errno));
  std::ostringstream text;
  text << file.rdbuf();
  return text.str();
}

Scenario LoadScenarioText(std::string_view text, const std::string& source_name) {
  Scenario scenario;
  scenario.source_path = source_name;
  SourceLocator locator(source_name, proto::Scenario::descriptor());
  ParseTextProtoOrThrow(text, source_name, &scenario.spec, locator.tree());
  scenario_internal::ValidateAndDerive(locator, &scenario);
  return scenario;
}

Scenario ValidateScenarioSpec(proto::Scenario spec, const std::string& source_name) {
  Scenario scenario;
  scenario.source_path = source_name;
  scenario.spec = std::move(spec);
  const SourceLocator locator(source_name, proto::Scenario::descriptor());  // No locations.
  scenario_internal::ValidateAndDerive(locator, &scenario);
  return scenario;
}

clock::Pacing Scenario::pacing() const {
  return spec.timing().pacing() == proto::Timing::PACING_LOCKSTEP ? clock::Pacing::kLockstep
                                                                  : clock::Pacing::kRealtime;
}

proto::Timing::Pacing ProtoPacing(clock::Pacing pacing) {
  return pacing == clock::Pacing::kLockstep ? proto::Timing::PACING_LOCKSTEP
                                            : proto::Timing::PACING_REALTIME;
}

Scenario LoadScenarioFile(const std::string& path) {
  return LoadScenarioText(ReadFileOrThrow(path, "scenario"), path);
}

void CheckAddressPlanAgainstRoutes(const Scenario& scenario,
                                   const std::vector<HostRoute>& host_routes) {
  const std::pair<const char*, Ipv4Prefix> ours[] = {{"wlan_subnet", scenario.wlan_subnet},
                                                     {"ctl_subnet", scenario.ctl_subnet}};
  for (const auto& [field, prefix] : ours) {
    for (const HostRoute& route : host_routes) {
      if (route.destination.length == 0) continue;
      if (prefix.Overlaps(route.destination)) {
        throw Error(scenario.source_path + ": addresses." + field + " " + FormatIpv4Prefix(prefix) +
                    " overlaps host route " + FormatIpv4Prefix(route.destination) + " dev " +
                    route.device + "; choose another subnet");
      }
    }
  }
}

}  // namespace sitlnet
