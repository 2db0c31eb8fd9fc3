#include "scenario/source_locator.h"

namespace sitlnet::scenario_internal {

using google::protobuf::Descriptor;
using google::protobuf::FieldDescriptor;
using google::protobuf::TextFormat;

SourceLocator::SourceLocator(std::string source_name, const Descriptor* root)
    : source_name_(std::move(source_name)), root_(root) {}

std::string SourceLocator::Where(std::span<const Step> path) const {
  const Descriptor* descriptor = root_;
  // ParseInfoTree's getters are non-const in protobuf 3.21.
  auto* tree = const_cast<TextFormat::ParseInfoTree*>(&tree_);
  int line = -1;
  int column = -1;
  for (const Step& step : path) {
    if (descriptor == nullptr || tree == nullptr) break;
    const FieldDescriptor* field = descriptor->FindFieldByName(std::string(step.field));
    if (field == nullptr) break;
    const auto location = tree->GetLocation(field, step.index);
    if (location.line < 0) break;
    line = location.line;
    column = location.column;
    if (field->type() != FieldDescriptor::TYPE_MESSAGE) break;
    tree = tree->GetTreeForNested(field, step.index);
    descriptor = field->message_type();
  }
  if (line < 0) return source_name_;
  return source_name_ + ":" + std::to_string(line + 1) + ":" + std::to_string(column + 1);
}

void SourceLocator::Fail(std::span<const Step> path, const std::string& message) const {
  throw Error(Where(path) + ": " + message);
}

}  // namespace sitlnet::scenario_internal
