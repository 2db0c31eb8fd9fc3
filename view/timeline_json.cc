#include "view/timeline_json.h"

#include "view/json_text.h"

namespace sitlnet::view {

void AppendIfChanged(TimeNs time_ns, int components, const std::vector<int>& component_of,
                     std::vector<ComponentsChange>* changes) {
  if (!changes->empty() && changes->back().component_of == component_of) return;
  changes->push_back({time_ns, components, component_of});
}

std::string TimelineMembers(const std::vector<ComponentsChange>& changes,
                            const std::vector<run_formats::SecondTiming>& timing) {
  std::string json =
      "\"connectivity\":" + Array(changes, [](const ComponentsChange& change) {
        return "[" + Seconds(change.time_ns) + "," + std::to_string(change.components) + "," +
               Array(change.component_of, [](int c) { return std::to_string(c); }) + "]";
      });
  json += ",\"timing\":" + Array(timing, [](const run_formats::SecondTiming& s) {
            return "[" + std::to_string(s.second) + "," + std::to_string(s.iterations) + "," +
                   Number(s.stf_mean) + "," + Number(s.stf_max) + "," +
                   Number(static_cast<double>(s.lag_max_ns) / kNsPerMs) + "]";
          });
  return json;
}

}  // namespace sitlnet::view
