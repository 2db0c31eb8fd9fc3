// A rate manager's state per destination, made when the destination is first
// met (ns-3 keeps one WifiRemoteStation per remote address). A flat vector:
// a station talks to a handful of destinations.
#ifndef SITLNET_MAC_PHY_SIM_PER_DESTINATION_H_
#define SITLNET_MAC_PHY_SIM_PER_DESTINATION_H_

#include <utility>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

template <typename Remote>
class PerDestination {
 public:
  // The state of `destination`, made by `make()` the first time.
  template <typename Make>
  Remote& Get(const MacAddress& destination, Make&& make) {
    for (auto& [mac, remote] : remotes_) {
      if (mac == destination) return remote;
    }
    return remotes_.emplace_back(destination, make()).second;
  }

 private:
  std::vector<std::pair<MacAddress, Remote>> remotes_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_PER_DESTINATION_H_
