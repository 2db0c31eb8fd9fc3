// pcap + radiotap encoding of on-air frames. Field layout from the radiotap
// standard (radiotap.org, "Defined fields"): each field aligned to its natural
// size, in the order of its bit in it_present.
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
// HT and VHT DATA frames: no Rate field (it cannot say an MCS), a pad byte before Channel, and
// after Antenna the MCS field (bit 19: known, flags, index; 3 bytes) or the VHT field (bit 21,
// 2-aligned: known u16, flags, bandwidth, mcs_nss[4], coding, group_id, partial_aid u16).
constexpr uint32_t kRadiotapPresentMcs = (kRadiotapPresent & ~(1u << 2)) | (1u << 19);
constexpr uint32_t kRadiotapPresentVht = (kRadiotapPresent & ~(1u << 2)) | (1u << 21);
constexpr size_t kRadiotapLengthMcs = 28;
constexpr size_t kRadiotapLengthVht = 38;  // 25, a pad byte to even, 12 bytes.
// An MPDU of an A-MPDU adds the A-MPDU status field (bit 20, 4-aligned: reference u32, flags
// u16, delimiter CRC, reserved; 8 bytes) after the MCS field (HT: 28 + 8 = 36) or before the
// VHT field (VHT: 25, 3 pad bytes, 8, then VHT at 36: 48).
constexpr uint32_t kRadiotapPresentAmpdu = 1u << 20;
constexpr size_t kRadiotapAmpduBytes = 8;
constexpr size_t kRadiotapLengthVhtAmpdu = 48;
constexpr uint16_t kAmpduLastKnown = 0x0004, kAmpduIsLast = 0x0008;
constexpr uint8_t kMcsKnownBandwidthIndexGiFec = 0x01 | 0x02 | 0x04 | 0x10;
constexpr uint16_t kVhtKnownGiBandwidth = 0x0004 | 0x0040;
constexpr uint8_t kRadiotapFlagFcsAtEnd = 0x10;
constexpr uint8_t kRadiotapFlagBadFcs = 0x40;
constexpr uint16_t kChannelOfdm = 0x0040;
constexpr uint16_t kChannelCck = 0x0020;
constexpr uint16_t kChannel2Ghz = 0x0080;
constexpr uint16_t kChannel5Ghz = 0x0100;

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
  std::vector<uint8_t> mpdu = mac::MpduBytes(frame.tx);
  // Frames the medium failed carry an inverted FCS, so the bad-FCS flag and the FCS agree.
  if (frame.failed) {
    for (size_t i = mpdu.size() - 4; i < mpdu.size(); ++i) mpdu[i] = ~mpdu[i];
  }
  return mpdu;
}

namespace {

// The MCS or VHT radiotap field of an HT/VHT frame (radiotap.org "MCS", "VHT").
// `vht_pad`: the byte that aligns the VHT field right after Antenna (offset 25).
void PutMcsField(const mac::TxRecord& tx, std::string* out, bool vht_pad = true) {
  if (!tx.vht) {
    out->push_back(static_cast<char>(kMcsKnownBandwidthIndexGiFec));
    // Bandwidth 0: 20, 1: 40 MHz; bit 2: short GI; FEC 0: BCC.
    const int flags = (tx.channel_width_mhz == 40 ? 1 : 0) | (tx.short_guard_interval ? 0x04 : 0);
    out->push_back(static_cast<char>(flags));
    out->push_back(static_cast<char>(tx.mcs));
    return;
  }
  if (vht_pad) out->push_back(0);  // Pad to the field's 2-byte alignment.
  PutLe16(out, kVhtKnownGiBandwidth);
  out->push_back(static_cast<char>(tx.short_guard_interval ? 0x04 : 0));
  // Bandwidth: 0: 20, 1: 40, 4: 80 MHz.
  out->push_back(static_cast<char>(tx.channel_width_mhz == 80 ? 4 : (tx.channel_width_mhz == 40)));
  out->push_back(static_cast<char>(tx.mcs << 4 | tx.spatial_streams));  // User 0: MCS, NSS.
  for (int user = 1; user < 4; ++user) out->push_back(0);
  out->push_back(0);  // Coding: BCC.
  out->push_back(0);  // Group ID: SU.
  PutLe16(out, 0);    // Partial AID.
}

void PutAmpduField(const mac::TxRecord& tx, std::string* out) {
  PutLe32(out, *tx.ampdu_reference);
  PutLe16(out, static_cast<uint16_t>(kAmpduLastKnown | (tx.ampdu_last ? kAmpduIsLast : 0)));
  out->push_back(0);  // Delimiter CRC (not known).
  out->push_back(0);  // Reserved.
}

}  // namespace

std::string EncodePcapRecord(const AirFrame& frame, TimeNs epoch_offset_ns) {
  const std::vector<uint8_t> mpdu = Encode80211Mpdu(frame);
  const bool mcs = frame.tx.mcs >= 0;
  const bool ampdu = mcs && frame.tx.ampdu_reference.has_value();
  size_t radiotap_length =
      !mcs ? kRadiotapLength : (frame.tx.vht ? kRadiotapLengthVht : kRadiotapLengthMcs);
  if (ampdu) radiotap_length = frame.tx.vht ? kRadiotapLengthVhtAmpdu : radiotap_length + kRadiotapAmpduBytes;
  const uint32_t captured = static_cast<uint32_t>(radiotap_length + mpdu.size());
  std::string out;
  out.reserve(16 + captured);
  const TimeNs ts = epoch_offset_ns + frame.tx.start_ns;
  PutLe32(&out, static_cast<uint32_t>(ts / kNsPerS));
  PutLe32(&out, static_cast<uint32_t>(ts % kNsPerS));
  PutLe32(&out, captured);
  PutLe32(&out, captured);
  // Radiotap header.
  out.push_back(0);  // it_version
  out.push_back(0);  // it_pad
  PutLe16(&out, static_cast<uint16_t>(radiotap_length));
  PutLe32(&out, (!mcs ? kRadiotapPresent
                      : (frame.tx.vht ? kRadiotapPresentVht : kRadiotapPresentMcs)) |
                    (ampdu ? kRadiotapPresentAmpdu : 0));
  PutLe64(&out, static_cast<uint64_t>(frame.tx.start_ns / kNsPerUs));  // TSFT, µs (offset 8)
  uint8_t flags = kRadiotapFlagFcsAtEnd;
  if (frame.failed) flags |= kRadiotapFlagBadFcs;
  out.push_back(static_cast<char>(flags));                                           // offset 16
  if (mcs) {
    out.push_back(0);  // No Rate field: pad Channel to its 2-byte alignment.
  } else {
    out.push_back(static_cast<char>(static_cast<int>(frame.tx.rate_mbps * 2 + 0.5)));  // 500 kb/s
  }
  int channel_mhz = frame.channel_mhz;
  if (channel_mhz == 0) channel_mhz = frame.band_5ghz ? 5180 : 2412;  // channel 36 / 1
  PutLe16(&out, static_cast<uint16_t>(channel_mhz));                  // offset 18
  PutLe16(&out, (frame.band_5ghz ? kChannel5Ghz : kChannel2Ghz) |
                    (frame.ofdm ? kChannelOfdm : kChannelCck));
  out.push_back(static_cast<char>(ClampDbm(frame.signal_dbm)));  // offset 22
  out.push_back(static_cast<char>(ClampDbm(frame.noise_dbm)));
  out.push_back(0);  // antenna 0
  if (ampdu && frame.tx.vht) {
    out.append(3, '\0');  // Offset 25 to the A-MPDU field's 4-byte alignment.
    PutAmpduField(frame.tx, &out);
    PutMcsField(frame.tx, &out, /*vht_pad=*/false);
  } else if (mcs) {
    PutMcsField(frame.tx, &out);
    if (ampdu) PutAmpduField(frame.tx, &out);  // At 28, 4-aligned.
  }
  out.append(reinterpret_cast<const char*>(mpdu.data()), mpdu.size());
  return out;
}

}  // namespace sitlnet::tapbridge
