// Masking what the robots' hosts decide in medium.pcap: what their kernels draw at random, and
// ArduCopter's logger health (moved here from tests/integration/autopilot_reproducibility_test.cc,
// which uses it too). Why these fields: docs/autopilots-evidence.md, "Reproducibility with the
// real autopilots".
#include <algorithm>
#include <cstdint>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

// Linux's default ip_local_port_range starts here: ports at or above it are ephemeral.
constexpr int kFirstEphemeralPort = 32768;

uint16_t Be16(const std::string& bytes, size_t at) {
  return static_cast<uint16_t>(static_cast<uint8_t>(bytes[at]) << 8 |
                               static_cast<uint8_t>(bytes[at + 1]));
}

// MAVLink's SYS_STATUS (message 1) and the bit of its onboard_control_sensors_health (a uint32 at
// payload byte 8) that says whether the logger works (MAV_SYS_STATUS_LOGGING, 0x01000000).
constexpr uint32_t kSysStatusMessage = 1;
constexpr size_t kSysStatusHealthAt = 8;
constexpr uint32_t kLoggingHealthBit = 0x01000000;

// In the MAVLink frames of one UDP payload [payload, end), the logger health bit of SYS_STATUS
// and the frame's checksum over it set to zero. ArduPilot reports its logger failed until its I/O
// thread, which the host schedules on its own clock, has started and beaten
// (AP_Logger_File::logging_failed, io_thread_alive): at boot that one bit depends on the host.
void WithoutLoggerHealth(std::string& pcap, size_t payload, size_t end) {
  const auto byte = [&](size_t i) { return static_cast<uint8_t>(pcap[i]); };
  for (size_t at = payload; at + 12 <= end;) {
    const bool v2 = byte(at) == 0xfd;
    if (!v2 && byte(at) != 0xfe) return;  // not MAVLink: the rest is left as it is
    const size_t length = byte(at + 1);
    const size_t header = v2 ? 10 : 6;
    const size_t signature = v2 && (byte(at + 2) & 0x01) != 0 ? 13 : 0;
    const size_t frame_end = at + header + length + 2 + signature;
    if (frame_end > end) return;
    const uint32_t message =
        v2 ? byte(at + 7) | byte(at + 8) << 8 | byte(at + 9) << 16 : byte(at + 5);
    if (message == kSysStatusMessage && length > kSysStatusHealthAt + 3) {
      const size_t health = at + header + kSysStatusHealthAt;
      for (size_t i = 0; i < 4; ++i) {
        pcap[health + i] = static_cast<char>(byte(health + i) & ~(kLoggingHealthBit >> (8 * i)));
      }
      pcap.replace(at + header + length, 2, 2, '\0');  // checksum
    }
    at = frame_end;
  }
}

}  // namespace

std::string WithoutHostDecidedFields(std::string pcap) {
  size_t at = 24;  // global header
  while (at + 16 <= pcap.size()) {
    const uint32_t length = static_cast<uint8_t>(pcap[at + 8]) |
                            static_cast<uint8_t>(pcap[at + 9]) << 8 |
                            static_cast<uint8_t>(pcap[at + 10]) << 16 |
                            static_cast<uint32_t>(static_cast<uint8_t>(pcap[at + 11])) << 24;
    const size_t frame = at + 16;
    const size_t end = frame + length;
    if (end > pcap.size() || length < 4) break;
    const size_t radiotap = static_cast<uint8_t>(pcap[frame + 2]) |
                            static_cast<uint8_t>(pcap[frame + 3]) << 8;
    const size_t mac = frame + radiotap;
    if (mac >= end) break;
    const uint8_t control = static_cast<uint8_t>(pcap[mac]);
    const bool data = (control & 0x0c) == 0x08;
    const size_t llc = mac + ((control & 0x80) != 0 ? 26 : 24);  // QoS data: 2 more
    if (data && llc + 8 + 20 <= end &&
        pcap.compare(llc, 8, "\xaa\xaa\x03\x00\x00\x00\x08\x00", 8) == 0) {
      const size_t ip = llc + 8;
      const size_t header = (static_cast<uint8_t>(pcap[ip]) & 0x0f) * 4u;
      const size_t ip_end = ip + Be16(pcap, ip + 2);
      pcap.replace(ip + 4, 2, 2, '\0');   // identification
      pcap.replace(ip + 10, 2, 2, '\0');  // header checksum
      if (pcap[ip + 9] == 17 && ip + header + 8 <= end) {
        const size_t udp = ip + header;
        for (size_t port : {udp, udp + 2}) {
          if (Be16(pcap, port) >= kFirstEphemeralPort) pcap.replace(port, 2, 2, '\0');
        }
        pcap.replace(udp + 6, 2, 2, '\0');  // checksum
        WithoutLoggerHealth(pcap, udp + 8, std::min(ip_end, end));
      }
      if (end == ip_end + 4) pcap.replace(ip_end, 4, 4, '\0');  // FCS
    }
    at = end;
  }
  return pcap;
}

}  // namespace sitlnet::verify
