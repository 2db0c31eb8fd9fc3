// sitlnet mac_phy_sim <- scenario: builds the medium a scenario describes.
// Separate library (sitlnet_mac_phy_sim_scenario) so that the simulator core
// does not depend on the scenario schema.
#ifndef SITLNET_MAC_PHY_SIM_SCENARIO_ADAPTER_H_
#define SITLNET_MAC_PHY_SIM_SCENARIO_ADAPTER_H_

#include "mac_phy_sim/mac_phy_sim.h"
#include "scenario/scenario.h"

namespace sitlnet::mac {

// The scenario's radio section and timing seed as a MediumConfig.
MediumConfig MediumConfigFromScenario(const sitlnet::Scenario& scenario);

// A medium with one station per robot (StationId == robot index, MAC
// RobotPlan::wlan_mac, initial position from the scenario) and every obstacle.
Medium MakeMediumFromScenario(const sitlnet::Scenario& scenario);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_SCENARIO_ADAPTER_H_
