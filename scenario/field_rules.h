// Checks a scenario message's fields against the rules their options declare
// (proto/sitlnet/field_options.proto): ranges and PHY rates, read by descriptor reflection, so a
// new field with options needs no validation code.
#ifndef SITLNET_SCENARIO_FIELD_RULES_H_
#define SITLNET_SCENARIO_FIELD_RULES_H_

#include <google/protobuf/descriptor.h>
#include <google/protobuf/message.h>

#include <string>
#include <vector>

#include "scenario/source_locator.h"
#include "sitlnet/scenario.pb.h"

namespace sitlnet::scenario_internal {

// The field whose rules `field` follows: the one its (same_rules_as) option names, else itself.
const google::protobuf::FieldDescriptor* RulesOf(const google::protobuf::FieldDescriptor* field);

// `value` of `field` as messages and docs print it: integer fields in full (31622400000),
// floating-point ones as an ostream does (16.0206, 1e+06, nan).
std::string NumberText(const google::protobuf::FieldDescriptor* field, double value);

// Checks every field of `message` that has a value (set, or with a proto2 default), and the fields
// of its set sub-messages, against its rules. `path` locates `message` in the file; `who`
// prefixes the message ("radio: "; a sub-message adds its field name and a space: "imu ").
// `standard` is the scenario's, for PHY rates. Fails on the first broken rule:
//   "<who><field> <value> out of range [<min>, <max>]"   both bounds, the lower one closed
//   "<who><field> <value> must be > <min>"                an open lower bound
//   "<who><field> <value> must be >= <min>"               a closed lower bound only
//   "<who><field> <value> must be at most <max>"          above the upper bound otherwise
//   "<who><field> <value> is not a rate of <standard> (802.11a: ...)"
void CheckFieldRules(const SourceLocator& at, std::vector<SourceLocator::Step> path,
                     const std::string& who, const google::protobuf::Message& message,
                     proto::Radio::Standard standard);

}  // namespace sitlnet::scenario_internal

#endif  // SITLNET_SCENARIO_FIELD_RULES_H_
