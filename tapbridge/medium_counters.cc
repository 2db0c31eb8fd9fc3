// MediumCounters <-> proto::StationCounters (tapbridge.h).
#include "sitlnet/medium.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

void AddCounts(const std::vector<std::pair<std::string, uint64_t>>& counts,
               google::protobuf::RepeatedPtrField<proto::NamedCount>* out) {
  for (const auto& [name, count] : counts) {
    proto::NamedCount* c = out->Add();
    c->set_name(name);
    c->set_count(count);
  }
}

void ReadCounts(const google::protobuf::RepeatedPtrField<proto::NamedCount>& in,
                std::vector<std::pair<std::string, uint64_t>>* out) {
  for (const proto::NamedCount& c : in) out->emplace_back(c.name(), c.count());
}

}  // namespace

void MediumCountersToProto(const MediumCounters& counters, proto::StationCounters* out) {
  out->set_sent(counters.sent);
  out->set_delivered(counters.delivered);
  out->set_queue_drops(counters.queue_drops);
  out->set_queue_expired(counters.queue_expired);
  AddCounts(counters.lost, out->mutable_lost());
  AddCounts(counters.other, out->mutable_other());
}

MediumCounters MediumCountersFromProto(const proto::StationCounters& in) {
  MediumCounters counters;
  counters.sent = in.sent();
  counters.delivered = in.delivered();
  counters.queue_drops = in.queue_drops();
  counters.queue_expired = in.queue_expired();
  ReadCounts(in.lost(), &counters.lost);
  ReadCounts(in.other(), &counters.other);
  return counters;
}

}  // namespace sitlnet::tapbridge
