#include <bit>
#include <concepts>
#include <cstring>
#include <type_traits>

#include "mavlink/mavlink.h"

namespace sitlnet::mavlink {
namespace {

// The host is little-endian (x86-64, aarch64) like MAVLink's payloads; a big-endian port fails
// here instead of on the wire.
static_assert(std::endian::native == std::endian::little, "MAVLink payloads are little-endian");

// Writes fields one after the other into a payload.
class Writer {
 public:
  template <typename T>
  Writer& operator()(const T& value) {
    if constexpr (std::is_arithmetic_v<T>) {
      std::memcpy(payload_.data() + offset_, &value, sizeof value);
      offset_ += sizeof value;
    } else {
      for (const auto& element : value) (*this)(element);
    }
    return *this;
  }
  const Payload& payload() const { return payload_; }

 private:
  Payload payload_{};
  size_t offset_ = 0;
};

// Reads fields one after the other from a frame's (zero-filled) payload.
class Reader {
 public:
  explicit Reader(const ReceivedFrame& frame) : payload_(frame.payload) {}
  template <typename T>
  Reader& operator()(T& value) {
    if constexpr (std::is_arithmetic_v<T>) {
      std::memcpy(&value, payload_.data() + offset_, sizeof value);
      offset_ += sizeof value;
    } else {
      for (auto& element : value) (*this)(element);
    }
    return *this;
  }

 private:
  const Payload& payload_;
  size_t offset_ = 0;
};

template <typename M, typename Message>
concept Is = std::same_as<std::remove_const_t<M>, Message>;

// Each message's fields in wire order (docs/references.md#mavlink), for both directions.
template <typename V, Is<Heartbeat> M>
void Fields(V& v, M& m) {
  v(m.custom_mode)(m.type)(m.autopilot)(m.base_mode)(m.system_status)(m.mavlink_version);
}
template <typename V, Is<GlobalPositionInt> M>
void Fields(V& v, M& m) {
  v(m.time_boot_ms)(m.lat)(m.lon)(m.alt)(m.relative_alt)(m.vx)(m.vy)(m.vz)(m.hdg);
}
template <typename V, Is<HilActuatorControls> M>
void Fields(V& v, M& m) {
  v(m.time_usec)(m.flags)(m.controls)(m.mode);
}
template <typename V, Is<HilSensor> M>
void Fields(V& v, M& m) {
  v(m.time_usec)(m.xacc)(m.yacc)(m.zacc)(m.xgyro)(m.ygyro)(m.zgyro)(m.xmag)(m.ymag)(m.zmag);
  v(m.abs_pressure)(m.diff_pressure)(m.pressure_alt)(m.temperature)(m.fields_updated);
  v(m.id);  // extension
}
template <typename V, Is<HilGps> M>
void Fields(V& v, M& m) {
  v(m.time_usec)(m.lat)(m.lon)(m.alt)(m.eph)(m.epv)(m.vel)(m.vn)(m.ve)(m.vd)(m.cog);
  v(m.fix_type)(m.satellites_visible);
  v(m.id)(m.yaw);  // extensions
}
template <typename V, Is<HilStateQuaternion> M>
void Fields(V& v, M& m) {
  v(m.time_usec)(m.attitude_quaternion)(m.rollspeed)(m.pitchspeed)(m.yawspeed)(m.lat)(m.lon);
  v(m.alt)(m.vx)(m.vy)(m.vz)(m.ind_airspeed)(m.true_airspeed)(m.xacc)(m.yacc)(m.zacc);
}

template <typename Message>
Payload PackFields(const Message& message) {
  Writer writer;
  Fields(writer, message);
  return writer.payload();
}

template <typename Message>
bool UnpackFields(const ReceivedFrame& frame, Message* message) {
  if (frame.message_id != IdOf(*message)) return false;
  Reader reader(frame);
  Fields(reader, *message);
  return true;
}

}  // namespace

Payload Pack(const Heartbeat& message) { return PackFields(message); }
Payload Pack(const GlobalPositionInt& message) { return PackFields(message); }
Payload Pack(const HilActuatorControls& message) { return PackFields(message); }
Payload Pack(const HilSensor& message) { return PackFields(message); }
Payload Pack(const HilGps& message) { return PackFields(message); }
Payload Pack(const HilStateQuaternion& message) { return PackFields(message); }

bool Unpack(const ReceivedFrame& frame, Heartbeat* message) { return UnpackFields(frame, message); }
bool Unpack(const ReceivedFrame& frame, GlobalPositionInt* message) {
  return UnpackFields(frame, message);
}
bool Unpack(const ReceivedFrame& frame, HilActuatorControls* message) {
  return UnpackFields(frame, message);
}
bool Unpack(const ReceivedFrame& frame, HilSensor* message) { return UnpackFields(frame, message); }
bool Unpack(const ReceivedFrame& frame, HilGps* message) { return UnpackFields(frame, message); }
bool Unpack(const ReceivedFrame& frame, HilStateQuaternion* message) {
  return UnpackFields(frame, message);
}

}  // namespace sitlnet::mavlink
