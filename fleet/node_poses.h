// A node's poses (its robots only, in its slice's order) checked and placed among the fleet's.
#ifndef SITLNET_FLEET_NODE_POSES_H_
#define SITLNET_FLEET_NODE_POSES_H_

#include <optional>
#include <string>
#include <vector>

#include "sitlnet/coordinator.pb.h"

namespace sitlnet::fleet {

// What is wrong with `poses` from a node of `robots` robots, as the end of a sentence ("sent
// poses of 3 robots, it has 2"); nullopt when it holds a position and an orientation per robot,
// and a velocity per robot or none, every number finite.
std::optional<std::string> FindBrokenPoses(const proto::coord::Poses& poses, size_t robots);

// Writes `node`'s poses (checked by FindBrokenPoses) to the places of `robots` in `all`, which
// holds every robot of the scenario. Velocities, when the node sends them, are placed too
// (`all` gains zeros for every robot first).
void PlacePoses(const proto::coord::Poses& node, const std::vector<int>& robots,
                proto::coord::Poses* all);

}  // namespace sitlnet::fleet

#endif  // SITLNET_FLEET_NODE_POSES_H_
