#include "runner/physics_options.h"

#include <gtest/gtest.h>
#include <stdlib.h>

#include <string>

#include "common/common.h"

namespace sitlnet::runner {
namespace {

// Sets the benchmark knobs for one test and removes them after.
class PhysicsOptionsTest : public ::testing::Test {
 protected:
  void TearDown() override {
    for (const char* name :
         {"SITLNET_PHYSICS_THREADS", "SITLNET_PHYSICS_INTEGRATOR", "SITLNET_PHYSICS_CULL_TILE_M"}) {
      unsetenv(name);
    }
  }
  static std::string ErrorOf() {
    try {
      PhysicsOptionsFromEnvironment();
    } catch (const Error& error) {
      return error.what();
    }
    return "";
  }
};

TEST_F(PhysicsOptionsTest, WithoutKnobsTheServersDefaultsStay) {
  const physics::ServerOptions defaults;
  const physics::ServerOptions options = PhysicsOptionsFromEnvironment();
  EXPECT_EQ(options.world.threads, defaults.world.threads);
  EXPECT_EQ(options.world.integrator, defaults.world.integrator);
  EXPECT_EQ(options.world.cull_obstacles, defaults.world.cull_obstacles);
  EXPECT_EQ(options.world.cull_tile_m, defaults.world.cull_tile_m);
}

TEST_F(PhysicsOptionsTest, EachKnobSetsItsOption) {
  setenv("SITLNET_PHYSICS_THREADS", "3", 1);
  setenv("SITLNET_PHYSICS_INTEGRATOR", "euler", 1);
  setenv("SITLNET_PHYSICS_CULL_TILE_M", "25", 1);
  const physics::ServerOptions options = PhysicsOptionsFromEnvironment();
  EXPECT_EQ(options.world.threads, 3);
  EXPECT_EQ(options.world.integrator, physics::Integrator::kEuler);
  EXPECT_TRUE(options.world.cull_obstacles);
  EXPECT_EQ(options.world.cull_tile_m, 25);
  setenv("SITLNET_PHYSICS_CULL_TILE_M", "0", 1);
  EXPECT_FALSE(PhysicsOptionsFromEnvironment().world.cull_obstacles);
}

TEST_F(PhysicsOptionsTest, ABadValueIsOneLineNamingTheVariable) {
  setenv("SITLNET_PHYSICS_THREADS", "65", 1);
  EXPECT_EQ(ErrorOf(), "SITLNET_PHYSICS_THREADS=\"65\": want 1..64");
  unsetenv("SITLNET_PHYSICS_THREADS");
  setenv("SITLNET_PHYSICS_INTEGRATOR", "verlet", 1);
  EXPECT_EQ(ErrorOf(), "SITLNET_PHYSICS_INTEGRATOR=\"verlet\": want euler or rk4");
  unsetenv("SITLNET_PHYSICS_INTEGRATOR");
  setenv("SITLNET_PHYSICS_CULL_TILE_M", "0.5", 1);
  EXPECT_EQ(ErrorOf(), "SITLNET_PHYSICS_CULL_TILE_M=\"0.5\": want 0 (no culling) or 1..1e6 m");
}

}  // namespace
}  // namespace sitlnet::runner
