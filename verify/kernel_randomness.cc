// Masking what the robots' kernels draw at random in medium.pcap (moved here from
// tests/integration/autopilot_reproducibility_test.cc, which uses it too). Why these fields:
// docs/autopilots-evidence.md, "Reproducibility with the real autopilots".
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

}  // namespace

std::string WithoutKernelRandomness(std::string pcap) {
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
      }
      if (end == ip_end + 4) pcap.replace(ip_end, 4, 4, '\0');  // FCS
    }
    at = end;
  }
  return pcap;
}

}  // namespace sitlnet::verify
