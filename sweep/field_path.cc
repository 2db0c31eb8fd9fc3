// --set's FIELD: a scalar field of the scenario by its path, set through protobuf reflection, so
// every field the schema has (and will have) can be swept without a list to keep up to date.
#include <google/protobuf/descriptor.h>
#include <google/protobuf/reflection.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

using google::protobuf::FieldDescriptor;
using google::protobuf::Message;

// One path segment: "robot[2]" -> {"robot", 2}; "radio" -> {"radio", nullopt}.
struct Segment {
  std::string name;
  std::optional<int> index;
};

Segment ParseSegment(const std::string& path, const std::string& text) {
  const size_t open = text.find('[');
  if (open == std::string::npos) {
    if (text.empty()) throw Error("an empty field name");
    return {text, std::nullopt};
  }
  const std::string digits = text.substr(open + 1, text.size() - open - 2);
  if (open == 0 || text.back() != ']' || digits.empty() || digits.size() > 6 ||
      digits.find_first_not_of("0123456789") != std::string::npos) {
    throw Error("\"" + text + "\" is not NAME or NAME[INDEX]");
  }
  return {text.substr(0, open), std::stoi(digits)};
}

std::string TypeWord(const FieldDescriptor& field) {
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
    case FieldDescriptor::CPPTYPE_FLOAT:
      return "a number";
    case FieldDescriptor::CPPTYPE_INT32:
    case FieldDescriptor::CPPTYPE_INT64:
      return "an integer";
    case FieldDescriptor::CPPTYPE_UINT32:
    case FieldDescriptor::CPPTYPE_UINT64:
      return "a non-negative integer";
    case FieldDescriptor::CPPTYPE_BOOL:
      return "true or false";
    case FieldDescriptor::CPPTYPE_ENUM: {
      std::string names;
      for (int i = 0; i < field.enum_type()->value_count(); ++i) {
        names += (i ? ", " : "") + field.enum_type()->value(i)->name();
      }
      return "one of " + names;
    }
    default:
      return "text";
  }
}

// Sets the singular scalar `field` of `message` from `value`; false if `value` is not of its type.
bool SetScalar(const FieldDescriptor& field, const std::string& value, Message* message) {
  const google::protobuf::Reflection& reflection = *message->GetReflection();
  char* end = nullptr;
  errno = 0;
  switch (field.cpp_type()) {
    case FieldDescriptor::CPPTYPE_DOUBLE:
    case FieldDescriptor::CPPTYPE_FLOAT: {
      const double number = std::strtod(value.c_str(), &end);
      if (*end != '\0' || errno == ERANGE || !std::isfinite(number)) return false;
      if (field.cpp_type() == FieldDescriptor::CPPTYPE_FLOAT) {
        reflection.SetFloat(message, &field, static_cast<float>(number));
      } else {
        reflection.SetDouble(message, &field, number);
      }
      return true;
    }
    case FieldDescriptor::CPPTYPE_INT32:
    case FieldDescriptor::CPPTYPE_INT64: {
      const long long number = std::strtoll(value.c_str(), &end, 10);
      if (*end != '\0' || errno == ERANGE) return false;
      if (field.cpp_type() == FieldDescriptor::CPPTYPE_INT32) {
        if (number < std::numeric_limits<int32_t>::min() ||
            number > std::numeric_limits<int32_t>::max()) {
          return false;
        }
        reflection.SetInt32(message, &field, static_cast<int32_t>(number));
      } else {
        reflection.SetInt64(message, &field, number);
      }
      return true;
    }
    case FieldDescriptor::CPPTYPE_UINT32:
    case FieldDescriptor::CPPTYPE_UINT64: {
      if (value.empty() || value[0] == '-') return false;
      const unsigned long long number = std::strtoull(value.c_str(), &end, 10);
      if (*end != '\0' || errno == ERANGE) return false;
      if (field.cpp_type() == FieldDescriptor::CPPTYPE_UINT32) {
        if (number > std::numeric_limits<uint32_t>::max()) return false;
        reflection.SetUInt32(message, &field, static_cast<uint32_t>(number));
      } else {
        reflection.SetUInt64(message, &field, number);
      }
      return true;
    }
    case FieldDescriptor::CPPTYPE_BOOL:
      if (value != "true" && value != "false") return false;
      reflection.SetBool(message, &field, value == "true");
      return true;
    case FieldDescriptor::CPPTYPE_ENUM: {
      const google::protobuf::EnumValueDescriptor* named = field.enum_type()->FindValueByName(value);
      if (named == nullptr) return false;
      reflection.SetEnum(message, &field, named);
      return true;
    }
    case FieldDescriptor::CPPTYPE_STRING:
      reflection.SetString(message, &field, value);
      return true;
    case FieldDescriptor::CPPTYPE_MESSAGE:
      return false;
  }
  return false;
}

}  // namespace

void SetFieldByPath(const std::string& path, const std::string& value, proto::Scenario* spec) {
  Message* message = spec;
  std::string walked;  // The path so far, for messages.
  size_t from = 0;
  while (true) {
    const size_t dot = path.find('.', from);
    const bool last = dot == std::string::npos;
    const Segment segment = ParseSegment(path, path.substr(from, last ? dot : dot - from));
    walked += (walked.empty() ? "" : ".") + segment.name;
    const FieldDescriptor* field = message->GetDescriptor()->FindFieldByName(segment.name);
    if (field == nullptr) {
      throw Error(message->GetDescriptor()->name() + " has no field \"" +
                  segment.name + "\"");
    }
    const google::protobuf::Reflection& reflection = *message->GetReflection();
    if (field->is_repeated() != segment.index.has_value()) {
      throw Error(walked +
                  (field->is_repeated() ? " is a list: name one element, " + walked + "[INDEX]"
                                        : " is not a list: no [INDEX]"));
    }
    const bool is_message = field->cpp_type() == FieldDescriptor::CPPTYPE_MESSAGE;
    if (last && (is_message || field->is_repeated())) {
      throw Error(walked + " is not a scalar field (name one of its fields)");
    }
    if (last) {
      if (!SetScalar(*field, value, message)) {
        throw Error("\"" + value + "\" is not " + TypeWord(*field));
      }
      return;
    }
    if (!is_message) throw Error(walked + " is a scalar, it has no fields");
    if (segment.index) {
      const int size = reflection.FieldSize(*message, field);
      if (*segment.index >= size) {
        throw Error("index " + std::to_string(*segment.index) + " past the scenario's " +
                    std::to_string(size) + " " + segment.name);
      }
      message = reflection.MutableRepeatedMessage(message, field, *segment.index);
      walked += "[" + std::to_string(*segment.index) + "]";
    } else {
      message = reflection.MutableMessage(message, field);
    }
    from = dot + 1;
  }
}

}  // namespace sitlnet::sweep
