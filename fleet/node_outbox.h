// The frames the bridge wrote to one node's robots, collected as the NodeWrites that goes down.
#ifndef SITLNET_FLEET_NODE_OUTBOX_H_
#define SITLNET_FLEET_NODE_OUTBOX_H_

#include <cstdint>
#include <span>
#include <string_view>
#include <unordered_map>

#include "common/common.h"
#include "sitlnet/node_link.pb.h"

namespace sitlnet::fleet {

// Each distinct frame crosses once: the bridge writes a broadcast to every receiver, one copy
// each, and a node of many robots would otherwise get it as many times.
class NodeOutbox {
 public:
  // Records that `frame` was written to `robot`, after every earlier write; `due_ns`: the
  // virtual time it was written (realtime), 0 in lockstep.
  void Add(int robot, std::span<const uint8_t> frame, TimeNs due_ns = 0);

  // Everything added since the last call, in order; the outbox is empty afterwards.
  proto::node::NodeWrites Take();

 private:
  proto::node::NodeWrites writes_;
  // Views into writes_.frames: a repeated string field keeps each element where it is while it
  // grows, so the views stay valid until Take.
  std::unordered_map<std::string_view, int> frame_index_;
};

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_NODE_OUTBOX_H_
