// Reading a point's summary.json (runner/summary.cc writes it) with protobuf's JSON parser, the
// JSON library the build already links.
#include <google/protobuf/util/json_util.h>

#include <fstream>
#include <sstream>

#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

const Value* Member(const Struct& object, const std::string& key) {
  const auto found = object.fields().find(key);
  return found == object.fields().end() ? nullptr : &found->second;
}

}  // namespace

std::optional<Struct> ReadSummaryJson(const std::string& path) {
  std::ifstream file(path);
  if (!file) return std::nullopt;
  std::stringstream text;
  text << file.rdbuf();
  Struct summary;
  if (!google::protobuf::util::JsonStringToMessage(text.str(), &summary).ok()) return std::nullopt;
  return summary;
}

bool IsFinishedSummary(const Struct& summary) {
  const Value* interrupted = Member(summary, "interrupted");
  const Value* failure = Member(summary, "failure");
  return interrupted != nullptr && interrupted->kind_case() == Value::kBoolValue &&
         !interrupted->bool_value() && failure != nullptr &&
         failure->kind_case() == Value::kNullValue;
}

std::optional<double> SummaryMetric(const Struct& summary, const std::string& path) {
  const Value* value = nullptr;
  const Struct* object = &summary;
  size_t from = 0;
  while (true) {
    const size_t dot = path.find('.', from);
    std::string segment = path.substr(from, dot == std::string::npos ? dot : dot - from);
    std::optional<int> index;
    const size_t open = segment.find('[');
    if (open != std::string::npos && segment.back() == ']') {
      index = std::atoi(segment.c_str() + open + 1);
      segment.resize(open);
    }
    if (object == nullptr) return std::nullopt;
    value = Member(*object, segment);
    if (value == nullptr) return std::nullopt;
    if (index) {
      if (value->kind_case() != Value::kListValue || *index < 0 ||
          *index >= value->list_value().values_size()) {
        return std::nullopt;
      }
      value = &value->list_value().values(*index);
    }
    if (dot == std::string::npos) break;
    object = value->kind_case() == Value::kStructValue ? &value->struct_value() : nullptr;
    from = dot + 1;
  }
  if (value->kind_case() == Value::kNumberValue) return value->number_value();
  if (value->kind_case() == Value::kBoolValue) return value->bool_value() ? 1.0 : 0.0;
  return std::nullopt;
}

std::vector<std::string> DefaultMetrics() {
  return {"metrics.stf.mean",
          "metrics.t_overhead_ms.mean",
          "metrics.overhead_share",
          "connectivity.max_components",
          "connectivity.time_split_s",
          "separation.min_m",
          "delivery.line_of_sight.ratio",
          "delivery.obstructed.ratio",
          "resources.loop_s"};
}

}  // namespace sitlnet::sweep
