#include "view/air_modes.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "mavlink/mavlink.h"
#include "view/autopilot_mode.h"

namespace sitlnet::view {
namespace {

constexpr size_t kFileHeaderBytes = 24;
constexpr size_t kRecordHeaderBytes = 16;
constexpr uint32_t kPcapMagicNanoseconds = 0xa1b23c4d;
constexpr uint32_t kLinktypeRadiotap = 127;
constexpr uint32_t kLargestRecordBytes = 1 << 16;  // Above sitlnet's snap length: a broken file.
constexpr uint32_t kRadiotapTsft = 1u << 0;
constexpr uint32_t kRadiotapExtended = 1u << 31;
constexpr size_t kRadiotapTsftOffset = 8;  // With no extended presence bitmap.
constexpr size_t kWlanHeaderBytes = 24;    // IBSS DATA: no QoS field, no address 4.
constexpr size_t kWlanTransmitterOffset = 10;
constexpr uint8_t kWlanRetry = 0x08;  // Frame Control, second byte.
constexpr size_t kSnapBytes = 8;      // RFC 1042 LLC/SNAP with the Ethernet type.
constexpr size_t kFcsBytes = 4;
constexpr uint8_t kIpProtocolUdp = 17;
constexpr size_t kUdpHeaderBytes = 8;

uint16_t Le16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | p[1] << 8); }
uint16_t Be16(const uint8_t* p) { return static_cast<uint16_t>(p[0] << 8 | p[1]); }
uint32_t Le32(const uint8_t* p) { return Le16(p) | static_cast<uint32_t>(Le16(p + 2)) << 16; }
uint64_t Le64(const uint8_t* p) { return Le32(p) | static_cast<uint64_t>(Le32(p + 4)) << 32; }

// Robot index of a RobotMac (02:00:00:00:hi:lo), or -1.
int RobotOfMac(const uint8_t* mac) {
  if (mac[0] != 0x02 || mac[1] != 0 || mac[2] != 0 || mac[3] != 0) return -1;
  return mac[4] << 8 | mac[5];
}

}  // namespace

AirModeReader::AirModeReader(int robots) : robots_(robots), latest_(robots, -1) {}

const ModeChange* AirModeReader::Latest(int robot) const {
  if (robot < 0 || robot >= robots_ || latest_[robot] < 0) return nullptr;
  return &changes_[latest_[robot]];
}

void AirModeReader::Push(const uint8_t* data, size_t size) {
  pending_.insert(pending_.end(), data, data + size);
  size_t used = 0;
  if (!header_read_) {
    if (pending_.size() < kFileHeaderBytes) return;
    if (Le32(pending_.data()) != kPcapMagicNanoseconds ||
        Le32(pending_.data() + 20) != kLinktypeRadiotap) {
      throw Error("not a pcap file of sitlnet's (nanosecond pcap, radiotap link type)");
    }
    header_read_ = true;
    used = kFileHeaderBytes;
  }
  while (pending_.size() - used >= kRecordHeaderBytes) {
    const uint32_t captured = Le32(pending_.data() + used + 8);
    if (captured > kLargestRecordBytes)
      throw Error("a pcap record of " + std::to_string(captured) + " bytes");
    if (pending_.size() - used - kRecordHeaderBytes < captured) break;
    Record(pending_.data() + used + kRecordHeaderBytes, captured);
    used += kRecordHeaderBytes + captured;
  }
  pending_.erase(pending_.begin(), pending_.begin() + static_cast<std::ptrdiff_t>(used));
}

void AirModeReader::Record(const uint8_t* record, size_t size) {
  if (size < 8) return;
  const size_t radiotap_bytes = Le16(record + 2);
  const uint32_t present = Le32(record + 4);
  if ((present & kRadiotapTsft) == 0 || (present & kRadiotapExtended) != 0 ||
      radiotap_bytes < kRadiotapTsftOffset + 8 ||
      size < radiotap_bytes + kWlanHeaderBytes + kSnapBytes + kFcsBytes) {
    return;
  }
  const TimeNs time_ns =
      static_cast<TimeNs>(Le64(record + kRadiotapTsftOffset)) * static_cast<TimeNs>(kNsPerUs);
  const uint8_t* wlan = record + radiotap_bytes;
  const size_t wlan_bytes = size - radiotap_bytes - kFcsBytes;
  const bool data_frame = (wlan[0] & 0x0c) == 0x08 && (wlan[0] & 0xf0) == 0;  // DATA, subtype 0
  if (!data_frame || (wlan[1] & kWlanRetry) != 0) return;
  const int robot = RobotOfMac(wlan + kWlanTransmitterOffset);
  if (robot < 0 || robot >= robots_) return;
  const uint8_t* snap = wlan + kWlanHeaderBytes;
  if (Be16(snap + 6) != 0x0800) return;  // IPv4
  const uint8_t* ip = snap + kSnapBytes;
  const size_t ip_bytes = wlan_bytes - kWlanHeaderBytes - kSnapBytes;
  if (ip_bytes < 20 || (ip[0] >> 4) != 4) return;
  const size_t ip_header_bytes = static_cast<size_t>(ip[0] & 0x0f) * 4;
  const bool fragment = (Be16(ip + 6) & 0x3fff) != 0;  // More Fragments, or an offset
  const size_t ip_total = Be16(ip + 2);
  if (ip[9] != kIpProtocolUdp || fragment || ip_total > ip_bytes ||
      ip_total < ip_header_bytes + kUdpHeaderBytes) {
    return;
  }
  const uint8_t* udp = ip + ip_header_bytes;
  const size_t udp_bytes = Be16(udp + 4);
  if (udp_bytes < kUdpHeaderBytes || udp_bytes > ip_total - ip_header_bytes) return;
  Datagram(time_ns, robot, udp + kUdpHeaderBytes, udp_bytes - kUdpHeaderBytes);
}

void AirModeReader::Datagram(TimeNs time_ns, int robot, const uint8_t* data, size_t size) {
  if (std::memchr(data, mavlink::kMagicV2, size) == nullptr) return;  // Most datagrams: no MAVLink.
  mavlink::FrameParser parser;
  parser.Push(data, size);
  mavlink::ReceivedFrame frame;
  while (parser.Next(&frame)) {
    mavlink::Heartbeat heartbeat;
    if (!mavlink::Unpack(frame, &heartbeat)) continue;
    std::string mode = AutopilotModeName(heartbeat);
    if (mode.empty()) continue;
    const ModeChange* latest = Latest(robot);
    if (latest != nullptr && latest->mode == mode) continue;
    latest_[robot] = static_cast<int>(changes_.size());
    changes_.push_back({time_ns, robot, std::move(mode)});
  }
}

std::vector<ModeChange> ReadAirModes(const std::string& pcap_path, int robots) {
  const UniqueFd file(open(pcap_path.c_str(), O_RDONLY | O_CLOEXEC));
  const int fd = file.get();
  if (fd < 0) {
    if (errno == ENOENT) return {};
    throw Error("open \"" + pcap_path + "\": " + std::strerror(errno));
  }
  AirModeReader reader(robots);
  std::vector<uint8_t> buffer(1 << 20);
  try {
    for (;;) {
      const ssize_t n = read(fd, buffer.data(), buffer.size());
      if (n < 0 && errno == EINTR) continue;
      if (n < 0) throw Error(std::string("read: ") + std::strerror(errno));
      if (n == 0) break;
      reader.Push(buffer.data(), static_cast<size_t>(n));
    }
  } catch (const Error& error) {
    throw Error("\"" + pcap_path + "\": " + error.what());
  }
  // Each robot's frames are in time order; the file interleaves robots by end of transmission.
  std::vector<ModeChange> changes = reader.changes();
  std::stable_sort(changes.begin(), changes.end(),
                   [](const ModeChange& a, const ModeChange& b) { return a.time_ns < b.time_ns; });
  return changes;
}

}  // namespace sitlnet::view
