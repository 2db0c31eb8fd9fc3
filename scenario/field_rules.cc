#include "scenario/field_rules.h"

#include <cmath>
#include <cstdlib>
#include <optional>
#include <sstream>

#include "scenario/radio_standard.h"
#include "sitlnet/field_options.pb.h"

namespace sitlnet::scenario_internal {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::FieldOptions;
using google::protobuf::Message;
using google::protobuf::Reflection;

// A numeric field's value as a number and as messages print it: integers in full (a duration of
// 31622400000 ms), floating point as an ostream does (16.0206, nan).
struct Value {
  double number = 0;
  std::string text;
};

// Six significant digits (the stream's default), or more where six would not give the value
// back: a default of 47.397742 must not read 47.3977.
std::string FloatText(double value) {
  for (int digits = 6;; ++digits) {
    std::ostringstream text;
    text.precision(digits);
    text << value;
    if (digits >= 17 || std::strtod(text.str().c_str(), nullptr) == value) return text.str();
  }
}

template <typename Integer>
Value IntegerValue(Integer value) {
  return Value{static_cast<double>(value), std::to_string(value)};
}

std::optional<Value> NumericValue(const Message& message, const FieldDescriptor* field) {
  const Reflection* reflection = message.GetReflection();
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE: {
      const double value = reflection->GetDouble(message, field);
      return Value{value, FloatText(value)};
    }
    case FieldDescriptor::CPPTYPE_FLOAT: {
      const double value = reflection->GetFloat(message, field);
      return Value{value, FloatText(value)};
    }
    case FieldDescriptor::CPPTYPE_INT32:
      return IntegerValue(reflection->GetInt32(message, field));
    case FieldDescriptor::CPPTYPE_INT64:
      return IntegerValue(reflection->GetInt64(message, field));
    case FieldDescriptor::CPPTYPE_UINT32:
      return IntegerValue(reflection->GetUInt32(message, field));
    case FieldDescriptor::CPPTYPE_UINT64:
      return IntegerValue(reflection->GetUInt64(message, field));
    default:
      return std::nullopt;
  }
}

// What breaks `rules`' range, or "" (see the forms in field_rules.h).
std::string RangeBreach(const FieldDescriptor* field, const FieldOptions& rules,
                        const Value& value) {
  const bool has_min = rules.HasExtension(proto::range_min);
  const bool has_max = rules.HasExtension(proto::range_max);
  if (!has_min && !has_max) return "";  // No declared range: the owner's code checks, if anyone.
  const double min = rules.GetExtension(proto::range_min);
  const double max = rules.GetExtension(proto::range_max);
  const bool open = rules.GetExtension(proto::range_min_open);
  const bool finite = std::isfinite(value.number);
  const bool below = has_min && (open ? !(value.number > min) : !(value.number >= min));
  const bool above = has_max && !(value.number <= max);
  if (finite && !below && !above) return "";
  if (has_min && has_max && !open) {
    return "out of range [" + NumberText(field, min) + ", " + NumberText(field, max) + "]";
  }
  if (has_min && (below || !finite)) {
    return (open ? "must be > " : "must be >= ") + NumberText(field, min);
  }
  return "must be at most " + NumberText(field, max);
}

}  // namespace

std::string NumberText(const FieldDescriptor* field, double value) {
  const bool integer = field->cpp_type() != FieldDescriptor::CPPTYPE_DOUBLE &&
                       field->cpp_type() != FieldDescriptor::CPPTYPE_FLOAT;
  return integer ? std::to_string(static_cast<int64_t>(value)) : FloatText(value);
}

const FieldDescriptor* RulesOf(const FieldDescriptor* field) {
  const std::string& name = field->options().GetExtension(proto::same_rules_as);
  if (name.empty()) return field;
  const FieldDescriptor* source = field->file()->pool()->FindFieldByName(name);
  SITLNET_DEMAND(source != nullptr);  // A misspelt name in scenario.proto: a bug, not input.
  return source;
}

void CheckFieldRules(const SourceLocator& at, std::vector<SourceLocator::Step> path,
                     const std::string& who, const Message& message,
                     proto::Radio::Standard standard) {
  const Reflection* reflection = message.GetReflection();
  const google::protobuf::Descriptor* descriptor = message.GetDescriptor();
  for (int i = 0; i < descriptor->field_count(); ++i) {
    const FieldDescriptor* field = descriptor->field(i);
    if (field->is_repeated()) continue;  // Lists (robots, obstacles) are walked by their owners.
    const bool set = reflection->HasField(message, field);
    path.push_back({field->name()});
    if (field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE) {
      if (set) {
        CheckFieldRules(at, path, who + field->name() + " ", reflection->GetMessage(message, field),
                        standard);
      }
      path.pop_back();
      continue;
    }
    // An unset field without a default has no value to check; a default is a value the file
    // chose by leaving the field out (the defaults' own ranges are checked in scenario_test).
    const std::optional<Value> value =
        set || field->has_default_value() ? NumericValue(message, field) : std::nullopt;
    if (value) {
      const FieldOptions& rules = RulesOf(field)->options();
      const std::string breach = RangeBreach(field, rules, *value);
      if (!breach.empty()) at.Fail(path, who + field->name() + " " + value->text + " " + breach);
      if (rules.GetExtension(proto::phy_rate) && !IsRateOf(standard, value->number)) {
        at.Fail(path, who + field->name() + " " + value->text + " is not a rate of " +
                          proto::Radio::Standard_Name(standard) + RateListsText());
      }
    }
    path.pop_back();
  }
}

}  // namespace sitlnet::scenario_internal
