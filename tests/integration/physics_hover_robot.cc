// A minimal onboard program for the physics integration test: links only the physics client
// library and protobuf, reads SITLNET_PHYSICS_ADDR, takes off and holds an altitude with a PD
// loop on the RobotState it receives over ctl0. Symmetric rotor speeds exert no torque, so the
// attitude stays level without an attitude loop.
//   physics_hover_robot --mass KG --kf N_PER_RAD2_S2 --max RAD_S --target-z M --duration-s S
// Prints "max_dev_m=<worst |z - target| over the last 2 s> final_z_m=<z> states=<n>".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>

#include "physics_mujoco/client/physics_client.h"

int main(int argc, char** argv) {
  double mass_kg = 0, kf = 0, max_rad_s = 0, target_z_m = 1, duration_s = 8;
  for (int i = 1; i + 1 < argc; i += 2) {
    const double value = std::atof(argv[i + 1]);
    if (!std::strcmp(argv[i], "--mass")) mass_kg = value;
    if (!std::strcmp(argv[i], "--kf")) kf = value;
    if (!std::strcmp(argv[i], "--max")) max_rad_s = value;
    if (!std::strcmp(argv[i], "--target-z")) target_z_m = value;
    if (!std::strcmp(argv[i], "--duration-s")) duration_s = value;
  }
  if (mass_kg <= 0 || kf <= 0 || max_rad_s <= 0) {
    std::fprintf(stderr, "physics_hover_robot: --mass, --kf and --max are required\n");
    return 2;
  }
  try {
    auto client = sitlnet::physics_client::PhysicsClient::FromEnvironment();
    client.SendRotorSpeeds({0, 0, 0, 0});  // subscribes: states go to the last command's sender
    constexpr double kG = 9.81;
    // Critically damped altitude loop, natural frequency 2 rad/s (settles in ~3 s).
    constexpr double kP = 4.0, kD = 4.0;
    double max_dev_m = 0, z_m = 0;
    int states = 0;
    sitlnet::proto::RobotState state;
    while (client.Receive(&state, 3000)) {
      ++states;
      z_m = state.position_m().z();
      const double t_s = state.sim_time_ns() / 1e9;
      if (t_s >= duration_s - 2) max_dev_m = std::max(max_dev_m, std::abs(z_m - target_z_m));
      if (t_s >= duration_s) {
        std::printf("max_dev_m=%.6f final_z_m=%.6f states=%d\n", max_dev_m, z_m, states);
        return 0;
      }
      const double accel = kG + kP * (target_z_m - z_m) - kD * state.velocity_m_s().z();
      const double thrust_n = std::max(0.0, mass_kg * accel);
      const double w = std::min(max_rad_s, std::sqrt(thrust_n / (4 * kf)));
      client.SendRotorSpeeds({w, w, w, w}, state.step());
    }
    std::fprintf(stderr, "physics_hover_robot: no state for 3 s after %d states\n", states);
    return 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "physics_hover_robot: %s\n", e.what());
    return 1;
  }
}
