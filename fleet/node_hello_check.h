// The central's check of a node host's Hello (role node): its name, the robots it claims and
// its initial poses, against the scenario's slices. Pure, so that the handshakes' threads and
// the fuzzer (fuzz/node_to_central_fuzz.cc) run the very same check.
#ifndef SITLNET_FLEET_NODE_HELLO_CHECK_H_
#define SITLNET_FLEET_NODE_HELLO_CHECK_H_

#include <string>
#include <vector>

#include "fleet/fleet.h"
#include "sitlnet/coordinator.pb.h"

namespace sitlnet::fleet {

// Why a node's Hello is refused ("node 'n1' claims robots b, but the scenario gives it b, d
// (another scenario or --node?)"), or "" when its name is one of `nodes`, it claims exactly that
// node's robots and sends their initial poses. Reads only its arguments.
std::string RefuseNodeHello(const Scenario& scenario, const std::vector<NodeSlice>& nodes,
                            const proto::coord::Hello& hello);

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_NODE_HELLO_CHECK_H_
