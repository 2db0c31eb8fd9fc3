// Maps fields of a parsed scenario back to file:line:col for error messages.
#ifndef SITLNET_SCENARIO_SOURCE_LOCATOR_H_
#define SITLNET_SCENARIO_SOURCE_LOCATOR_H_

#include <google/protobuf/text_format.h>

#include <memory>
#include <span>
#include <string>
#include <string_view>

#include "common/common.h"

namespace sitlnet::scenario_internal {

// Wraps protobuf's ParseInfoTree. A path is a sequence of (field, index)
// steps from the root message; the deepest step that has a location wins, so
// a missing field is reported at its enclosing message.
class SourceLocator {
 public:
  struct Step {
    std::string_view field;
    int index = -1;  // -1 for a singular field.
  };

  SourceLocator(std::string source_name, const google::protobuf::Descriptor* root);

  google::protobuf::TextFormat::ParseInfoTree* tree() { return &tree_; }

  // "source:line:col" for the path (line/col from 1), or "source" if unknown.
  std::string Where(std::span<const Step> path) const;
  std::string Where(std::initializer_list<Step> path) const { return Where(Span(path)); }

  // Throws Error("<Where(path)>: <message>").
  [[noreturn]] void Fail(std::span<const Step> path, const std::string& message) const;
  [[noreturn]] void Fail(std::initializer_list<Step> path, const std::string& message) const {
    Fail(Span(path), message);
  }

 private:
  // C++20's span has no constructor from an initializer_list (C++26 adds one).
  static std::span<const Step> Span(std::initializer_list<Step> path) {
    return {path.begin(), path.size()};
  }

  std::string source_name_;
  const google::protobuf::Descriptor* root_;
  google::protobuf::TextFormat::ParseInfoTree tree_;
};

}  // namespace sitlnet::scenario_internal

#endif  // SITLNET_SCENARIO_SOURCE_LOCATOR_H_
