// Scenarios and helpers shared by the physics_mujoco unit tests.
#ifndef SITLNET_PHYSICS_MUJOCO_TEST_TEST_SCENARIOS_H_
#define SITLNET_PHYSICS_MUJOCO_TEST_TEST_SCENARIOS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "physics_mujoco/physics_mujoco.h"
#include "scenario/scenario.h"

namespace sitlnet::physics::testing {

// A scenario with `body` inserted (robots, obstacles, airframes...). Its ctl subnet is on the
// loopback network (127.77.0.0/16: robot i's server at 127.77.0.(4i+1), robot side .(4i+2)),
// so protocol tests run without privileges; physics_port is unique to this process.
// `timing` is added inside its timing block (e.g. "physics_integrator: INTEGRATOR_EULER");
// `physics_step_us` must divide the 10 ms iteration.
Scenario MakeScenario(const std::string& body, const std::string& timing = "",
                      int physics_step_us = 1000);

// UDP port of the physics server in MakeScenario's scenarios, and a second free one.
uint16_t TestPhysicsPort();
uint16_t TestJsonPort();

// Waits (poll) until `fd` is readable or `timeout_ms` passes; true if readable.
bool WaitReadable(int fd, int timeout_ms);

// Server options with the frame gate (lockstep pacing) at `timeout_ns`.
ServerOptions FrameGate(TimeNs timeout_ns);
// Expects every double of the two poses equal (==, bit for bit); `where` names the place.
void ExpectSamePose(const RobotPose& a, const RobotPose& b, const std::string& where);

// The robots of server->TakeSilentAutopilots(), in its order.
std::vector<int> TakeSilentRobots(PhysicsServer* server);

}  // namespace sitlnet::physics::testing

#endif  // SITLNET_PHYSICS_MUJOCO_TEST_TEST_SCENARIOS_H_
