#include "runner/physics_options.h"

#include <cstdlib>
#include <string>

#include "common/common.h"

namespace sitlnet::runner {

physics::ServerOptions PhysicsOptionsFromEnvironment() {
  physics::ServerOptions options;
  if (const char* threads = std::getenv("SITLNET_PHYSICS_THREADS"); threads && *threads) {
    char* end = nullptr;
    const long value = std::strtol(threads, &end, 10);
    if (*end != '\0' || value < 1 || value > 64) {
      throw Error(std::string("SITLNET_PHYSICS_THREADS=\"") + threads + "\": want 1..64");
    }
    options.world.threads = static_cast<int>(value);
  }
  if (const char* integrator = std::getenv("SITLNET_PHYSICS_INTEGRATOR");
      integrator && *integrator) {
    const std::string name = integrator;
    if (name != "euler" && name != "rk4") {
      throw Error("SITLNET_PHYSICS_INTEGRATOR=\"" + name + "\": want euler or rk4");
    }
    options.world.integrator =
        name == "euler" ? physics::Integrator::kEuler : physics::Integrator::kRk4;
  }
  // SITLNET_PHYSICS_CULL_TILE_M=M: obstacle tiles of M metres; 0: no culling (docs/physics.md).
  if (const char* tile = std::getenv("SITLNET_PHYSICS_CULL_TILE_M"); tile && *tile) {
    char* end = nullptr;
    const double value = std::strtod(tile, &end);
    // 0 or at least a metre: a tile index is the position over the tile size, as an int64.
    if (*end != '\0' || !(value == 0 || (value >= 1 && value <= 1e6))) {
      throw Error(std::string("SITLNET_PHYSICS_CULL_TILE_M=\"") + tile +
                  "\": want 0 (no culling) or 1..1e6 m");
    }
    options.world.cull_obstacles = value > 0;
    if (value > 0) options.world.cull_tile_m = value;
  }
  return options;
}

}  // namespace sitlnet::runner
