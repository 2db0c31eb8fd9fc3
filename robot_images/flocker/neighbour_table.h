// Neighbours the flocker has heard from on wlan0, forgotten after a timeout
// of its own (virtual) clock without news.
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_NEIGHBOUR_TABLE_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_NEIGHBOUR_TABLE_H_

#include <cstdint>
#include <map>
#include <vector>

#include "robot_images/flocker/flocking.h"

namespace sitlnet::flocker {

class NeighbourTable {
 public:
  explicit NeighbourTable(int64_t timeout_ns) : timeout_ns_(timeout_ns) {}

  // Records what robot `index` said, heard at local virtual time `now_ns`.
  void Heard(uint32_t index, const Neighbour& state, int64_t now_ns);

  // Drops neighbours silent for longer than the timeout; returns the rest.
  std::vector<Neighbour> Current(int64_t now_ns);

  // Indices currently known (after the last Current()).
  std::vector<uint32_t> Indices() const;

 private:
  struct Entry {
    Neighbour state;
    int64_t heard_ns = 0;
  };
  int64_t timeout_ns_;
  std::map<uint32_t, Entry> entries_;
};

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_NEIGHBOUR_TABLE_H_
