// ArduPilot JSON backend servo packets (binary, little-endian) and what the server does with an
// accepted one: frame tracking and PWM -> rotor speed.
#include <cstddef>
#include <cstdint>

#include "physics_mujoco/ardupilot_json.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static sitlnet::physics::FrameTracker tracker;
  const auto packet = sitlnet::physics::ParseServoPacket(data, size);
  if (!packet) return 0;
  if (packet->channels != 16 && packet->channels != 32) __builtin_trap();
  if (packet->frame_rate_hz == 0) __builtin_trap();
  uint64_t missed = 0;
  tracker.OnFrame(packet->frame_count, &missed);
  constexpr double kMaxSpeedRadS = 1000;
  const auto speeds = sitlnet::physics::PwmToRotorSpeeds(*packet, kMaxSpeedRadS);
  for (double speed : speeds) {
    if (!(speed >= 0 && speed <= kMaxSpeedRadS)) __builtin_trap();
  }
  return 0;
}
