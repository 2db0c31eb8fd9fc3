// WorldSimulator: physics alone as a coordinator's connector, and the START checks every physics
// connector makes of what the coordinator sends.
#include <gtest/gtest.h>

#include <limits>
#include <string>

#include "physics_side/physics_side.h"

namespace sitlnet::physics_side {
namespace {

// A Start's times come from another process (a fleet's central, issue 35): any pair is refused
// in one line unless it spans the iteration. end - start overflowed for the widest pair
// (undefined behaviour; found reading what a node applies to its central's messages).
TEST(WorldSimulatorTest, AStartOfAnySpanButTheIterationsIsRefusedInOneLine) {
  const Scenario scenario = LoadScenarioText(
      "name: \"span\"\nrobot { name: \"a\" position_m { z: 5 } }\n", "span.textproto");
  physics::World world(scenario);
  WorldSimulator simulator(scenario, &world);
  struct : coordinator::IterationContext {
    void CommandsCollected() override {}
  } context;
  const auto refusal = [&](TimeNs start_ns, TimeNs end_ns) -> std::string {
    proto::coord::Start start;
    start.set_start_ns(start_ns);
    start.set_end_ns(end_ns);
    proto::coord::End end;
    try {
      simulator.RunIteration(start, &end, context);
    } catch (const Error& e) {
      return e.what();
    }
    return "accepted";
  };
  EXPECT_EQ(refusal(0, scenario.iteration_ns), "accepted");
  EXPECT_EQ(refusal(std::numeric_limits<TimeNs>::min(), std::numeric_limits<TimeNs>::max()),
            "physics connector: START of iteration 0 spans more than an int64 of ns, expected 10 "
            "steps of 1000000 ns");
  EXPECT_EQ(refusal(5, 4),
            "physics connector: START of iteration 0 spans -1 ns, expected 10 steps of 1000000 ns");
}

}  // namespace
}  // namespace sitlnet::physics_side
