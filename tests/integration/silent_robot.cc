// A robot program for the fault tests: joins the lock-step, answers the first N states with a
// command for their step, then stays silent (it still reads, it just never answers), as a
// wedged autopilot would. Links only the physics client library.
//   silent_robot N
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "physics_mujoco/client/physics_client.h"

int main(int argc, char** argv) {
  const int answers = argc > 1 ? std::atoi(argv[1]) : 0;
  try {
    auto client = sitlnet::physics_client::PhysicsClient::FromEnvironment();
    client.SendThrottles({0, 0, 0, 0});  // Subscribes and joins the lock-step.
    sitlnet::proto::RobotState state;
    int answered = 0;
    while (client.Receive(&state, -1)) {
      if (answered < answers) {
        client.SendThrottles({0, 0, 0, 0}, state.step());
        ++answered;
      } else if (answered == answers) {
        std::printf("silent_robot: going silent at step %llu\n",
                    static_cast<unsigned long long>(state.step()));
        std::fflush(stdout);
        ++answered;  // Silent from now on.
      }
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "silent_robot: %s\n", e.what());
    return 1;
  }
}
