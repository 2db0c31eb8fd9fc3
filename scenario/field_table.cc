#include "scenario/field_table.h"

#include "common/common.h"
#include "scenario/field_rules.h"
#include "scenario/radio_standard.h"
#include "sitlnet/field_options.pb.h"
#include "sitlnet/scenario.pb.h"

namespace sitlnet {
namespace {

using google::protobuf::FieldDescriptor;
using scenario_internal::NumberText;

constexpr char kBegin[] = "<!-- scenario-doc: ";
constexpr char kEnd[] = "<!-- scenario-doc end -->";

std::string DefaultText(const FieldDescriptor* field) {
  if (!field->has_default_value()) {
    const std::string& unset = field->options().GetExtension(proto::unset_means);
    return unset.empty() ? "" : "unset: " + unset;
  }
  switch (field->cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
      return NumberText(field, field->default_value_double());
    case FieldDescriptor::CPPTYPE_INT64:
      return std::to_string(field->default_value_int64());
    case FieldDescriptor::CPPTYPE_UINT32:
      return std::to_string(field->default_value_uint32());
    case FieldDescriptor::CPPTYPE_UINT64:
      return std::to_string(field->default_value_uint64());
    case FieldDescriptor::CPPTYPE_BOOL:
      return field->default_value_bool() ? "true" : "false";
    case FieldDescriptor::CPPTYPE_ENUM:
      return "`" + field->default_value_enum()->name() + "`";
    default:
      return field->default_value_string();
  }
}

// The declared rule, as field_rules.cc enforces it.
std::string RuleText(const FieldDescriptor* field) {
  const auto& rules = scenario_internal::RulesOf(field)->options();
  const bool has_min = rules.HasExtension(proto::range_min);
  const bool has_max = rules.HasExtension(proto::range_max);
  const std::string min = NumberText(field, rules.GetExtension(proto::range_min));
  const std::string max = NumberText(field, rules.GetExtension(proto::range_max));
  std::string rule;
  if (rules.GetExtension(proto::range_min_open)) {
    rule = "> " + min + (has_max ? ", at most " + max : "");
  } else if (has_min && has_max) {
    rule = "[" + min + ", " + max + "]";
  } else if (has_min) {
    rule = "≥ " + min;
  } else if (has_max) {
    rule = "at most " + max;
  }
  if (rules.GetExtension(proto::phy_rate)) {
    // RateListsText() is " (802.11a: ...; 802.11b: ...; 802.11g: both)": a table cell drops
    // the parentheses.
    const std::string lists = RateListsText();
    rule = "a rate of the standard: " + lists.substr(2, lists.size() - 3);
  }
  const std::string& own_help = field->options().GetExtension(proto::help);
  const std::string& help = own_help.empty() ? rules.GetExtension(proto::help) : own_help;
  if (rule.empty()) return help;
  return help.empty() ? rule : rule + "; " + help;
}

// " text |", or " |" for an empty cell.
std::string Cell(const std::string& text) { return text.empty() ? " |" : " " + text + " |"; }

}  // namespace

std::string FieldTable(const google::protobuf::Descriptor* message) {
  std::string table = "| field | unit | default | rule / source |\n| --- | --- | --- | --- |\n";
  for (int i = 0; i < message->field_count(); ++i) {
    const FieldDescriptor* field = message->field(i);
    const auto& options = scenario_internal::RulesOf(field)->options();
    table += "| `" + field->name() + "` |" + Cell(options.GetExtension(proto::unit)) +
             Cell(DefaultText(field)) + Cell(RuleText(field)) + "\n";
  }
  return table;
}

std::string WithFieldTables(const std::string& page) {
  std::string out;
  size_t at = 0;
  while (true) {
    const size_t begin = page.find(kBegin, at);
    if (begin == std::string::npos) break;
    const size_t name_end = page.find(" -->\n", begin);
    const size_t end = page.find(kEnd, begin);
    if (name_end == std::string::npos || end == std::string::npos) {
      throw Error("scenario-doc: a block opened at byte " + std::to_string(begin) + " has no end");
    }
    const std::string name =
        page.substr(begin + sizeof kBegin - 1, name_end - begin - (sizeof kBegin - 1));
    const google::protobuf::Descriptor* message =
        proto::Scenario::descriptor()->file()->FindMessageTypeByName(name);
    if (message == nullptr) throw Error("scenario-doc: no message " + name + " in scenario.proto");
    out += page.substr(at, name_end + 5 - at) + FieldTable(message);
    at = end;
  }
  return out + page.substr(at);
}

}  // namespace sitlnet
