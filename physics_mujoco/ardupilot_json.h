// ArduPilot's JSON SITL physics-backend protocol (docs/references.md#ardupilot-json, from
// ArduPilot's libraries/SITL/examples/JSON/readme.md): servo packets in, "\n{json}\n" state out,
// frame_count driven lock-step.
#ifndef SITLNET_PHYSICS_MUJOCO_ARDUPILOT_JSON_H_
#define SITLNET_PHYSICS_MUJOCO_ARDUPILOT_JSON_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

inline constexpr uint16_t kServoMagic16 = 18458;  // 16 channels, 40 bytes
inline constexpr uint16_t kServoMagic32 = 29569;  // 32 channels (SERVO_32_ENABLE), 72 bytes

struct ServoPacket {
  uint16_t frame_rate_hz = 0;
  uint32_t frame_count = 0;
  int channels = 0;  // 16 or 32
  std::array<uint16_t, 32> pwm_us{};
};

// The lowest frame rate accepted. Each new frame advances physics by 1/frame_rate on the shared
// physics thread, so a robot claiming 1 Hz would cost 1000 steps (at 1 ms) per packet and
// stall every other robot (issue 17, finding 9); 50 Hz bounds a frame to 20 ms of physics.
inline constexpr uint16_t kMinJsonFrameRateHz = 50;

// Little-endian decoding. nullopt: wrong magic, wrong size for the magic, or frame_rate below
// kMinJsonFrameRateHz.
std::optional<ServoPacket> ParseServoPacket(const void* data, size_t size);

// What a frame_count means relative to the previous one (readme: it increments per frame, is
// repeated when SITL re-sends, and restarts when SITL restarts).
enum class FrameAction {
  kNewFrame,  // First frame or larger count: advance physics by 1/frame_rate, reply.
  kResend,    // Same count: reply with the last state again, physics unchanged.
  kRestart,   // Smaller count: reset the vehicle, then handle as the first frame.
};

class FrameTracker {
 public:
  // `missed` receives the number of skipped counts (count jumped by more than 1).
  FrameAction OnFrame(uint32_t frame_count, uint64_t* missed);
  void Reset() { has_last_ = false; }

 private:
  bool has_last_ = false;
  uint32_t last_ = 0;
};

// PWM (us) -> rotor speed: throttle = clamp((pwm - 1000) / 1000, 0, 1), speed =
// throttle * max_speed (thrust then grows with throttle^2). Channels 1..4 drive rotors 1..4.
RotorSpeeds PwmToRotorSpeeds(const ServoPacket& packet, double max_speed_rad_s);

// "\n{...}\n" with timestamp (s), imu.gyro and imu.accel_body (FRD), position and velocity
// (NED) and quaternion (w, x, y, z, NED/FRD), and no_time_sync (SITL takes its pace from the
// replies alone), keys without spaces.
std::string FormatJsonState(TimeNs sim_time_ns, const RobotPose& pose, const ImuSample& imu);
// The same into `out`, replacing its contents: a reused string keeps its buffer, so a reply
// per frame allocates nothing.
void FormatJsonStateInto(TimeNs sim_time_ns, const RobotPose& pose, const ImuSample& imu,
                         std::string* out);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_ARDUPILOT_JSON_H_
