// The physics server's MotorCommand decoding + validation (DecodeMotorCommand is exactly what
// physics_server.cc runs on every datagram from a robot's ctl0).
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "physics_mujoco/robot_codec.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  constexpr double kMaxSpeedRadS = 1000;
  sitlnet::physics::DecodedCommand command;
  const auto verdict =
      sitlnet::physics::DecodeMotorCommand(data, size, /*robot_index=*/1, kMaxSpeedRadS, &command);
  if (verdict == sitlnet::physics::CommandVerdict::kAccepted) {
    // Accepted commands are finite and within [0, max]: the physics never sees anything else.
    for (double speed : command.target_rad_s) {
      if (!(speed >= 0 && speed <= kMaxSpeedRadS)) __builtin_trap();
    }
  }
  return 0;
}
