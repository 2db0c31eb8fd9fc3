// --set robot_count=N: the fleet size as a sweep axis. A scenario's robots differ in name,
// position, image and arguments, so no rule could make new ones that a user would expect; a
// point keeps the first N of the robots the scenario lists, which the user chose and can read.
#include <string>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

// A whole decimal number from 1 to `most`, or 0.
int ParseCount(const std::string& text, int most) {
  if (text.empty() || text.size() > 6 || text.find_first_not_of("0123456789") != std::string::npos) {
    return 0;
  }
  const int count = std::stoi(text);
  return count <= most ? count : 0;
}

}  // namespace

void KeepFirstRobots(const std::string& value, proto::Scenario* spec) {
  const int listed = spec->robot_size();
  const int count = ParseCount(value, listed);
  if (count == 0) {
    throw Error("\"" + value + "\" is not a robot count from 1 to the " + std::to_string(listed) +
                " robots the scenario lists (robot_count keeps the first N)");
  }
  spec->mutable_robot()->DeleteSubrange(count, listed - count);
}

void SetAxisValue(const std::string& field_path, const std::string& value,
                  proto::Scenario* spec) {
  if (field_path == kRobotCountField) {
    KeepFirstRobots(value, spec);
  } else {
    SetFieldByPath(field_path, value, spec);
  }
}

}  // namespace sitlnet::sweep
