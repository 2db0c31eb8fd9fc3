#include "robot_images/flocker/neighbour_table.h"

namespace sitlnet::flocker {

void NeighbourTable::Heard(uint32_t index, const Neighbour& state, int64_t now_ns) {
  entries_[index] = Entry{state, now_ns};
}

std::vector<Neighbour> NeighbourTable::Current(int64_t now_ns) {
  std::vector<Neighbour> result;
  for (auto it = entries_.begin(); it != entries_.end();) {
    if (now_ns - it->second.heard_ns > timeout_ns_) {
      it = entries_.erase(it);
    } else {
      result.push_back(it->second.state);
      ++it;
    }
  }
  return result;
}

std::vector<uint32_t> NeighbourTable::Indices() const {
  std::vector<uint32_t> indices;
  for (const auto& [index, entry] : entries_) indices.push_back(index);
  return indices;
}

}  // namespace sitlnet::flocker
