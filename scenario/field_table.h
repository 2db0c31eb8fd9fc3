// docs/scenario.md's field tables, printed from scenario.proto's options (field_options.proto):
// each field's unit, default, range and help are said once, in the schema.
#ifndef SITLNET_SCENARIO_FIELD_TABLE_H_
#define SITLNET_SCENARIO_FIELD_TABLE_H_

#include <google/protobuf/descriptor.h>

#include <string>

namespace sitlnet {

// The Markdown table of `message`'s fields, one row each in declaration order:
// "| field | unit | default | rule / source |". The rule is the declared range or rate rule,
// then the field's help, joined by "; ".
std::string FieldTable(const google::protobuf::Descriptor* message);

// `page` with every generated block replaced by FieldTable of the message it names: a block is
// the lines between "<!-- scenario-doc: <Message> -->" and "<!-- scenario-doc end -->".
// Throws Error for an unknown message or an unterminated block.
std::string WithFieldTables(const std::string& page);

}  // namespace sitlnet

#endif  // SITLNET_SCENARIO_FIELD_TABLE_H_
