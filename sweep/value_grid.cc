// The sweep's grid: --set and --seeds parsing, combinations x seeds, point folder names.
#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <set>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

std::vector<std::string> SplitOn(std::string_view text, char separator) {
  std::vector<std::string> parts;
  size_t from = 0;
  while (true) {
    const size_t at = text.find(separator, from);
    parts.emplace_back(text.substr(from, at == std::string_view::npos ? at : at - from));
    if (at == std::string_view::npos) return parts;
    from = at + 1;
  }
}

// A whole decimal unsigned number, or nullopt.
std::optional<uint64_t> ParseUnsigned(const std::string& text) {
  if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  errno = 0;
  const unsigned long long value = std::strtoull(text.c_str(), nullptr, 10);
  if (errno == ERANGE) return std::nullopt;
  return value;
}

// Values become part of a folder name: '/' cannot be in one, '%' escapes it.
std::string EscapeForFolder(const std::string& value) {
  std::string escaped;
  for (char c : value) {
    if (c == '/') {
      escaped += "%2F";
    } else if (c == '%') {
      escaped += "%25";
    } else {
      escaped += c;
    }
  }
  return escaped;
}

// Linux's NAME_MAX.
constexpr size_t kMaxFolderNameLength = 255;
// Seeds in one list: a typo such as "1-1000000000" should not start a billion runs.
constexpr uint64_t kMaxSeeds = 100000;

}  // namespace

SweepAxis ParseSetFlag(std::string_view text) {
  const std::string flag = "--set " + std::string(text);
  const size_t equals = text.find('=');
  if (equals == std::string_view::npos || equals == 0) {
    throw Error(flag + ": expected FIELD=V1,V2,...");
  }
  SweepAxis axis;
  axis.field_path = std::string(text.substr(0, equals));
  axis.values = SplitOn(text.substr(equals + 1), ',');
  std::set<std::string> seen;
  for (const std::string& value : axis.values) {
    if (value.empty()) throw Error(flag + ": an empty value");
    if (!seen.insert(value).second) throw Error(flag + ": value \"" + value + "\" twice");
  }
  return axis;
}

std::vector<uint64_t> ParseSeedList(std::string_view text) {
  const std::string flag = "--seeds " + std::string(text);
  std::set<uint64_t> seeds;
  for (const std::string& item : SplitOn(text, ',')) {
    const size_t dash = item.find('-');
    const std::optional<uint64_t> first = ParseUnsigned(item.substr(0, dash));
    const std::optional<uint64_t> last =
        dash == std::string::npos ? first : ParseUnsigned(item.substr(dash + 1));
    if (!first || !last) throw Error(flag + ": \"" + item + "\" is not N or N-M");
    if (*last < *first) throw Error(flag + ": \"" + item + "\" ends before it starts");
    if (*last - *first >= kMaxSeeds || seeds.size() + (*last - *first) >= kMaxSeeds) {
      throw Error(flag + ": more than " + std::to_string(kMaxSeeds) + " seeds");
    }
    for (uint64_t seed = *first; seed <= *last; ++seed) seeds.insert(seed);
  }
  return {seeds.begin(), seeds.end()};
}

std::vector<SweepPoint> ExpandGrid(const std::vector<SweepAxis>& axes,
                                   const std::vector<uint64_t>& seeds) {
  size_t combinations = 1;
  for (const SweepAxis& axis : axes) combinations *= axis.values.size();
  std::vector<SweepPoint> points;
  for (size_t combination = 0; combination < combinations; ++combination) {
    // Mixed-radix digits of `combination`, the last axis the fastest.
    std::vector<std::string> values(axes.size());
    size_t rest = combination;
    for (size_t a = axes.size(); a-- > 0;) {
      values[a] = axes[a].values[rest % axes[a].values.size()];
      rest /= axes[a].values.size();
    }
    for (uint64_t seed : seeds) {
      points.push_back({static_cast<int>(combination), values, seed,
                        PointFolderName(axes, values, seed)});
    }
  }
  return points;
}

std::string PointFolderName(const std::vector<SweepAxis>& axes,
                            const std::vector<std::string>& values, uint64_t seed) {
  SITLNET_DEMAND(axes.size() == values.size());
  std::string name;
  for (size_t a = 0; a < axes.size(); ++a) {
    name += axes[a].field_path + "=" + EscapeForFolder(values[a]) + ",";
  }
  name += "seed=" + std::to_string(seed);
  if (name.size() > kMaxFolderNameLength) {
    throw Error("point folder \"" + name + "\": longer than " +
                std::to_string(kMaxFolderNameLength) + " characters (fewer or shorter --set)");
  }
  return name;
}

}  // namespace sitlnet::sweep
