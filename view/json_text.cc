#include "view/json_text.h"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace sitlnet::view {

std::string Quote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (static_cast<unsigned char>(c) < 0x20) {
      char escaped[8];
      std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
      out += escaped;
    } else {
      if (c == '"' || c == '\\') out += '\\';
      out += c;
    }
  }
  return out + "\"";
}

std::string Number(double value) {
  if (!std::isfinite(value)) return "null";
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

std::string Seconds(TimeNs ns) { return Number(static_cast<double>(ns) / kNsPerS); }

std::string Vec3(const proto::Vec3& v) {
  return "[" + Number(v.x()) + "," + Number(v.y()) + "," + Number(v.z()) + "]";
}

std::string LinkArray(int64_t second, int from, int to, uint64_t frames, uint64_t delivered,
                      double ratio, const std::string& main_cause, uint64_t main_cause_frames) {
  return "[" + std::to_string(second) + "," + std::to_string(from) + "," + std::to_string(to) +
         "," + std::to_string(frames) + "," + std::to_string(delivered) + "," +
         (ratio < 0 ? "null" : Number(ratio)) + "," + Quote(main_cause) + "," +
         std::to_string(main_cause_frames) + "]";
}

std::string ModeChangesArray(const std::vector<ModeChange>& changes) {
  return Array(changes, [](const ModeChange& change) {
    return "[" + Seconds(change.time_ns) + "," + std::to_string(change.robot) + "," +
           Quote(change.mode) + "]";
  });
}

}  // namespace sitlnet::view
