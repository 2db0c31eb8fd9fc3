// Fallback while mac_phy_sim is not part of the build: only the relay medium.
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {

std::unique_ptr<MediumModel> MakeMacPhySimMedium(const Scenario& scenario) {
  throw Error("this build has no mac_phy_sim library: only the relay medium is available");
}

}  // namespace sitlnet::tapbridge
