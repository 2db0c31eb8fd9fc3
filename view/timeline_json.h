// The timeline the page draws under the map, live and replayed: the connectivity components
// (connectivity.csv) where they change, and the iterations' timing per second (metrics.csv).
#ifndef SITLNET_VIEW_TIMELINE_JSON_H_
#define SITLNET_VIEW_TIMELINE_JSON_H_

#include <string>
#include <vector>

#include "common/common.h"
#include "run_formats/run_formats.h"

namespace sitlnet::view {

// A connectivity.csv row whose components differ from the row before (in count or members).
struct ComponentsChange {
  TimeNs time_ns = 0;
  int components = 0;
  std::vector<int> component_of;  // Per robot: its component's smallest robot index.
};

// Appends the row (time_ns, components, component_of) to `changes` unless it equals the last.
void AppendIfChanged(TimeNs time_ns, int components, const std::vector<int>& component_of,
                     std::vector<ComponentsChange>* changes);

// "connectivity": [[time_s, components, [component_of...]], ...], "timing": [[second,
// iterations, stf_mean, stf_max, lag_max_ms], ...]: two members of a JSON object, no braces.
std::string TimelineMembers(const std::vector<ComponentsChange>& changes,
                            const std::vector<run_formats::SecondTiming>& timing);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_TIMELINE_JSON_H_
