// pcap + radiotap encoding of on-air frames. Field layout from the radiotap
// standard (radiotap.org, "Defined fields"): each field aligned to its natural
// size, in the order of its bit in it_present.
#include <zlib.h>

#include <cstring>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

constexpr uint32_t kPcapMagicNanoseconds = 0xa1b23c4d;
constexpr uint32_t kLinktypeIeee80211Radiotap = 127;  // DLT_IEEE802_11_RADIO
constexpr uint32_t kSnapLength = 65535;

// it_present bits: TSFT(0) Flags(1) Rate(2) Channel(3) dBm signal(5)
// dBm noise(6) Antenna(11). 8-byte header + 8 + 1 + 1 + 4 + 1 + 1 + 1 = 25.
constexpr uint32_t kRadiotapPresent =
    (1u << 0) | (1u << 1) | (1u << 2) | (1u << 3) | (1u << 5) | (1u << 6) | (1u << 11);
constexpr size_t kRadiotapLength = 25;
constexpr uint8_t kRadiotapFlagFcsAtEnd = 0x10;
constexpr uint8_t kRadiotapFlagBadFcs = 0x40;
constexpr uint16_t kChannelOfdm = 0x0040;
constexpr uint16_t kChannelCck = 0x0020;
constexpr uint16_t kChannel2Ghz = 0x0080;
constexpr uint16_t kChannel5Ghz = 0x0100;

// The IBSS's BSSID (addr3 of data frames): one locally administered address
// for every scenario; the medium is one ad hoc cell.
constexpr uint8_t kBssid[6] = {0x02, 0x73, 0x69, 0x74, 0x6c, 0x6e};

void PutLe16(std::string* out, uint16_t v) {
  out->push_back(static_cast<char>(v & 0xff));
  out->push_back(static_cast<char>(v >> 8));
}
void PutLe32(std::string* out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void PutLe64(std::string* out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out->push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}
void PutMac(std::vector<uint8_t>* out, const uint8_t* mac) {
  out->insert(out->end(), mac, mac + 6);
}
void PutLe16(std::vector<uint8_t>* out, uint16_t v) {
  out->push_back(v & 0xff);
  out->push_back(v >> 8);
}

int8_t ClampDbm(double dbm) {
  if (dbm > 127) return 127;
  if (dbm < -128) return -128;
  return static_cast<int8_t>(dbm < 0 ? dbm - 0.5 : dbm + 0.5);
}

}  // namespace

std::string PcapFileHeader() {
  std::string out;
  PutLe32(&out, kPcapMagicNanoseconds);
  PutLe16(&out, 2);  // version 2.4
  PutLe16(&out, 4);
  PutLe32(&out, 0);  // thiszone
  PutLe32(&out, 0);  // sigfigs
  PutLe32(&out, kSnapLength);
  PutLe32(&out, kLinktypeIeee80211Radiotap);
  return out;
}

std::vector<uint8_t> Encode80211Mpdu(const AirFrame& frame) {
  if (frame.mpdu.size() >= 4) {
    std::vector<uint8_t> mpdu = frame.mpdu;
    if (frame.failed) {
      for (size_t i = mpdu.size() - 4; i < mpdu.size(); ++i) mpdu[i] = ~mpdu[i];
    }
    return mpdu;
  }
  std::vector<uint8_t> mpdu;
  mpdu.reserve(frame.ethernet.size() + 32);
  const uint8_t flags = frame.retry ? 0x08 : 0x00;  // FC flags byte: Retry (9.2.4.1.7)
  switch (frame.kind) {
    case AirFrameKind::kData: {
      // Data, ToDS = FromDS = 0 (IBSS): addr1 DA, addr2 SA, addr3 BSSID (9.3.2.1).
      mpdu.push_back(0x08);
      mpdu.push_back(flags);
      PutLe16(&mpdu, frame.duration_field_us);
      const std::vector<uint8_t>& eth = frame.ethernet;
      if (eth.size() >= 14) {
        PutMac(&mpdu, eth.data());      // DA
        PutMac(&mpdu, eth.data() + 6);  // SA
      } else {
        PutMac(&mpdu, frame.receiver.bytes.data());
        PutMac(&mpdu, frame.sender.bytes.data());
      }
      PutMac(&mpdu, kBssid);
      PutLe16(&mpdu, static_cast<uint16_t>((frame.sequence & 0x0fff) << 4));
      // LLC/SNAP (RFC 1042) carrying the Ethernet type, then the payload.
      const uint8_t snap[6] = {0xaa, 0xaa, 0x03, 0x00, 0x00, 0x00};
      mpdu.insert(mpdu.end(), snap, snap + 6);
      if (eth.size() >= 14) {
        mpdu.insert(mpdu.end(), eth.begin() + 12, eth.end());
      } else {
        mpdu.push_back(0x08);
        mpdu.push_back(0x00);
      }
      break;
    }
    case AirFrameKind::kAck:  // Control, subtype 13: FC d4 00, Duration, RA.
    case AirFrameKind::kCts:  // Control, subtype 12: FC c4 00, Duration, RA.
      mpdu.push_back(frame.kind == AirFrameKind::kAck ? 0xd4 : 0xc4);
      mpdu.push_back(0x00);
      PutLe16(&mpdu, frame.duration_field_us);
      PutMac(&mpdu, frame.receiver.bytes.data());
      break;
    case AirFrameKind::kRts:  // Control, subtype 11: FC b4 00, Duration, RA, TA.
      mpdu.push_back(0xb4);
      mpdu.push_back(0x00);
      PutLe16(&mpdu, frame.duration_field_us);
      PutMac(&mpdu, frame.receiver.bytes.data());
      PutMac(&mpdu, frame.sender.bytes.data());
      break;
  }
  // FCS: CRC-32 of the MPDU (9.2.4.8), little-endian; inverted for frames the
  // medium failed, so the bad-FCS flag and the FCS agree.
  uint32_t fcs = static_cast<uint32_t>(crc32(0L, mpdu.data(), static_cast<uInt>(mpdu.size())));
  if (frame.failed) fcs = ~fcs;
  for (int i = 0; i < 4; ++i) mpdu.push_back((fcs >> (8 * i)) & 0xff);
  return mpdu;
}

std::string EncodePcapRecord(const AirFrame& frame, TimeNs epoch_offset_ns) {
  const std::vector<uint8_t> mpdu = Encode80211Mpdu(frame);
  const uint32_t captured = static_cast<uint32_t>(kRadiotapLength + mpdu.size());
  std::string out;
  out.reserve(16 + captured);
  const TimeNs ts = epoch_offset_ns + frame.start_ns;
  PutLe32(&out, static_cast<uint32_t>(ts / kNsPerS));
  PutLe32(&out, static_cast<uint32_t>(ts % kNsPerS));
  PutLe32(&out, captured);
  PutLe32(&out, captured);
  // Radiotap header.
  out.push_back(0);  // it_version
  out.push_back(0);  // it_pad
  PutLe16(&out, kRadiotapLength);
  PutLe32(&out, kRadiotapPresent);
  PutLe64(&out, static_cast<uint64_t>(frame.start_ns / kNsPerUs));  // TSFT, µs (offset 8)
  uint8_t flags = kRadiotapFlagFcsAtEnd;
  if (frame.failed) flags |= kRadiotapFlagBadFcs;
  out.push_back(static_cast<char>(flags));                                        // offset 16
  out.push_back(static_cast<char>(static_cast<int>(frame.rate_mbps * 2 + 0.5)));  // 500 kb/s
  int channel_mhz = frame.channel_mhz;
  if (channel_mhz == 0) channel_mhz = frame.band_5ghz ? 5180 : 2412;  // channel 36 / 1
  PutLe16(&out, static_cast<uint16_t>(channel_mhz));                  // offset 18
  PutLe16(&out, (frame.band_5ghz ? kChannel5Ghz : kChannel2Ghz) |
                    (frame.ofdm ? kChannelOfdm : kChannelCck));
  out.push_back(static_cast<char>(ClampDbm(frame.signal_dbm)));  // offset 22
  out.push_back(static_cast<char>(ClampDbm(frame.noise_dbm)));
  out.push_back(0);  // antenna 0
  out.append(reinterpret_cast<const char*>(mpdu.data()), mpdu.size());
  return out;
}

}  // namespace sitlnet::tapbridge
