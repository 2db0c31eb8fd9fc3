#include "physics_mujoco/ardupilot_json.h"

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "physics_mujoco/frames.h"

namespace sitlnet::physics {
namespace {

uint16_t Le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
uint32_t Le32(const uint8_t* p) {
  return uint32_t{p[0]} | (uint32_t{p[1]} << 8) | (uint32_t{p[2]} << 16) | (uint32_t{p[3]} << 24);
}

void AppendVector(const char* key, const Vec3d& v, std::string* out) {
  char text[160];
  std::snprintf(text, sizeof text, "\"%s\":[%.9g,%.9g,%.9g]", key, v.x, v.y, v.z);
  *out += text;
}

}  // namespace

std::optional<ServoPacket> ParseServoPacket(const void* data, size_t size) {
  const auto* bytes = static_cast<const uint8_t*>(data);
  if (size < 8) return std::nullopt;
  ServoPacket packet;
  const uint16_t magic = Le16(bytes);
  if (magic == kServoMagic16 && size == 8 + 2 * 16) {
    packet.channels = 16;
  } else if (magic == kServoMagic32 && size == 8 + 2 * 32) {
    packet.channels = 32;
  } else {
    return std::nullopt;
  }
  packet.frame_rate_hz = Le16(bytes + 2);
  packet.frame_count = Le32(bytes + 4);
  if (packet.frame_rate_hz < kMinJsonFrameRateHz) return std::nullopt;
  for (int i = 0; i < packet.channels; ++i) packet.pwm_us[i] = Le16(bytes + 8 + 2 * i);
  return packet;
}

FrameAction FrameTracker::OnFrame(uint32_t frame_count, uint64_t* missed) {
  *missed = 0;
  FrameAction action = FrameAction::kNewFrame;
  if (has_last_) {
    if (frame_count == last_) return FrameAction::kResend;
    if (frame_count < last_) {
      action = FrameAction::kRestart;
    } else {
      *missed = frame_count - last_ - 1;
    }
  }
  has_last_ = true;
  last_ = frame_count;
  return action;
}

RotorSpeeds PwmToRotorSpeeds(const ServoPacket& packet, double max_speed_rad_s) {
  RotorSpeeds speeds{};
  for (int i = 0; i < kRotors; ++i) {
    const double throttle = std::clamp((packet.pwm_us[i] - 1000.0) / 1000.0, 0.0, 1.0);
    speeds[i] = throttle * max_speed_rad_s;
  }
  return speeds;
}

std::string FormatJsonState(TimeNs sim_time_ns, const RobotPose& pose, const ImuSample& imu) {
  std::string out;
  FormatJsonStateInto(sim_time_ns, pose, imu, &out);
  return out;
}

void FormatJsonStateInto(TimeNs sim_time_ns, const RobotPose& pose, const ImuSample& imu,
                         std::string* out_string) {
  std::string& out = *out_string;
  out = "\n{";
  char text[64];
  std::snprintf(text, sizeof text, "\"timestamp\":%.9f,",
                static_cast<double>(sim_time_ns) / kNsPerS);
  out += text;
  out += "\"imu\":{";
  AppendVector("gyro", FluToFrd(imu.gyro_rad_s), &out);
  out += ",";
  AppendVector("accel_body", FluToFrd(imu.accel_m_s2), &out);
  out += "},";
  AppendVector("position", EnuToNed(pose.position_m), &out);
  out += ",";
  const Quat q = EnuFluToNedFrd(pose.orientation);
  char quat[160];
  std::snprintf(quat, sizeof quat, "\"quaternion\":[%.9g,%.9g,%.9g,%.9g],", q.w, q.x, q.y, q.z);
  out += quat;
  AppendVector("velocity", EnuToNed(pose.velocity_m_s), &out);
  // sitlnet's clock paces SITL (the frame gate, the realtime hold): without this SITL also
  // sleeps to hold each frame to 1/frame_rate of wall time (SIM_Aircraft's sync_frame_time), so
  // a lockstep run could never go faster than real time.
  out += ",\"no_time_sync\":1}\n";
}

}  // namespace sitlnet::physics
