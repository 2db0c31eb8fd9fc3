// Small JSON text builders for the view's documents (no library: numbers, strings, arrays).
#ifndef SITLNET_VIEW_JSON_TEXT_H_
#define SITLNET_VIEW_JSON_TEXT_H_

#include <string>
#include <vector>

#include "common/common.h"
#include "run_formats/run_formats.h"
#include "sitlnet/scenario.pb.h"
#include "view/air_modes.h"

namespace sitlnet::view {

// `text` as a JSON string, quotes included.
std::string Quote(const std::string& text);
// The shortest text that reads back as `value` ("null" if not finite).
std::string Number(double value);
std::string Seconds(TimeNs ns);
std::string Vec3(const proto::Vec3& v);

template <typename Item, typename Format>
std::string Array(const std::vector<Item>& items, Format format) {
  std::string json = "[";
  for (size_t i = 0; i < items.size(); ++i) json += (i ? "," : "") + format(items[i]);
  return json + "]";
}

// A links.csv row as the page reads it: [second, from, to, frames, delivered, ratio|null,
// main_cause, main_cause_frames]; `ratio` < 0 for none.
std::string LinkArray(int64_t second, int from, int to, uint64_t frames, uint64_t delivered,
                      double ratio, const std::string& main_cause, uint64_t main_cause_frames);

// Autopilot mode changes as [[time_s, robot, mode], ...], in the order given.
std::string ModeChangesArray(const std::vector<ModeChange>& changes);

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_JSON_TEXT_H_
