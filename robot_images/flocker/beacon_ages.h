// How old the neighbours' beacons were when the flocker read them, over one log period: the
// delay the radio added to the flock's control traffic (docs/howto-qos.md).
#ifndef SITLNET_ROBOT_IMAGES_FLOCKER_BEACON_AGES_H_
#define SITLNET_ROBOT_IMAGES_FLOCKER_BEACON_AGES_H_

#include <cstdint>
#include <string>
#include <vector>

namespace sitlnet::flocker {

class BeaconAges {
 public:
  // Records one beacon sent at the sender's virtual `sent_ns` and read at local virtual `read_ns`
  // (one clock for the whole run). Its age resolves to the state period the flocker reads in.
  void Add(int64_t sent_ns, int64_t read_ns) { ages_ns_.push_back(read_ns - sent_ns); }

  // "P50/MAX" in whole milliseconds of the ages since the last call (the median is the lower
  // middle value), or "-" if no beacon came; then forgets them.
  std::string TakeSummaryMs();

 private:
  std::vector<int64_t> ages_ns_;
};

}  // namespace sitlnet::flocker

#endif  // SITLNET_ROBOT_IMAGES_FLOCKER_BEACON_AGES_H_
