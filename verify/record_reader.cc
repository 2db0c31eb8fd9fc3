// Reading the run record of summary.json (runner/summary.cc writes it) with protobuf's JSON
// parser, the JSON library the build already links.
#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

using google::protobuf::Struct;
using google::protobuf::Value;

const Value* Member(const Struct& object, const std::string& key, Value::KindCase kind) {
  const auto found = object.fields().find(key);
  if (found == object.fields().end() || found->second.kind_case() != kind) return nullptr;
  return &found->second;
}

}  // namespace

RunRecord ReadRunRecord(const std::string& run_dir) {
  const std::string path = run_dir + "/summary.json";
  const std::string text = ReadFileOrThrow(path, "run summary");
  Struct summary;
  if (!google::protobuf::util::JsonStringToMessage(text, &summary).ok()) {
    throw Error(path + ": not a whole JSON object (the run did not finish writing it?)");
  }
  if (Member(summary, "outputs", Value::kNullValue) != nullptr) {
    throw Error(path + ": \"outputs\" is null: the run could not hash its outputs (its stderr "
                "says why); run the scenario again");
  }
  const Value* outputs = Member(summary, "outputs", Value::kStructValue);
  const Value* scenario_text = Member(summary, "scenario_text", Value::kStringValue);
  const Value* pacing = Member(summary, "pacing", Value::kStringValue);
  const Value* seed = Member(summary, "seed", Value::kNumberValue);
  if (outputs == nullptr || scenario_text == nullptr || pacing == nullptr || seed == nullptr) {
    throw Error(path + ": no run record (\"outputs\", \"scenario_text\"): written by a sitlnet "
                "older than `sitlnet verify`; run the scenario again");
  }
  RunRecord record;
  record.run_dir = run_dir;
  record.scenario_text = scenario_text->string_value();
  record.pacing = pacing->string_value();
  // JSON numbers are doubles: seeds past 2^53 would not survive, the record's text does.
  record.seed = static_cast<uint64_t>(seed->number_value());
  if (const Value* source = Member(summary, "source", Value::kStringValue)) {
    record.source = source->string_value();
  }
  if (const Value* version = Member(summary, "sitlnet_version", Value::kStringValue)) {
    record.version = version->string_value();
  }
  if (const Value* interrupted = Member(summary, "interrupted", Value::kBoolValue)) {
    record.interrupted = interrupted->bool_value();
  }
  for (const auto& [file, entry] : outputs->struct_value().fields()) {
    const Value* sha256 = entry.kind_case() == Value::kStructValue
                              ? Member(entry.struct_value(), "sha256", Value::kStringValue)
                              : nullptr;
    if (sha256 == nullptr) throw Error(path + ": outputs \"" + file + "\" has no sha256");
    RecordedOutput& output = record.outputs[file];
    output.sha256 = sha256->string_value();
    if (const Value* bytes = Member(entry.struct_value(), "bytes", Value::kNumberValue)) {
      output.bytes = static_cast<int64_t>(bytes->number_value());
    }
  }
  return record;
}

void RefuseUnreproducible(const RunRecord& record) {
  if (record.pacing != "PACING_LOCKSTEP") {
    throw Error(record.run_dir + " was run in " + record.pacing +
                ": its outputs follow the host's timing, so no run reproduces them; verify "
                "checks lockstep runs (sitlnet run --pacing lockstep)");
  }
  if (record.interrupted) {
    throw Error(record.run_dir + " was interrupted: it stopped at a wall-clock instant that no "
                "rerun can repeat");
  }
}

}  // namespace sitlnet::verify
