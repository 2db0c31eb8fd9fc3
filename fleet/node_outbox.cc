#include "fleet/node_outbox.h"

#include <string>

namespace sitlnet::fleet {

void NodeOutbox::Add(int robot, std::span<const uint8_t> frame, TimeNs due_ns) {
  const std::string_view bytes(reinterpret_cast<const char*>(frame.data()), frame.size());
  int index = 0;
  if (const auto known = frame_index_.find(bytes); known != frame_index_.end()) {
    index = known->second;
  } else {
    std::string* stored = writes_.add_frames();
    stored->assign(bytes);
    index = writes_.frames_size() - 1;
    frame_index_.emplace(std::string_view(*stored), index);  // Views the stored copy.
  }
  proto::node::NodeWrites::Write* write = writes_.add_writes();
  write->set_robot(robot);
  write->set_frame_index(index);
  write->set_due_ns(due_ns);
}

proto::node::NodeWrites NodeOutbox::Take() {
  frame_index_.clear();
  proto::node::NodeWrites taken;
  taken.Swap(&writes_);
  return taken;
}

}  // namespace sitlnet::fleet
