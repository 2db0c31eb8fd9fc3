#include "mac_phy_sim/mpdu.h"

#include <array>

namespace sitlnet::mac {
namespace {

std::array<uint32_t, 256> MakeCrcTable() {
  std::array<uint32_t, 256> table{};
  for (uint32_t i = 0; i < 256; ++i) {
    uint32_t c = i;
    for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
    table[i] = c;
  }
  return table;
}

void Put16(std::vector<uint8_t>* out, uint16_t v) {  // Little endian, as 802.11 fields are.
  out->push_back(static_cast<uint8_t>(v & 0xff));
  out->push_back(static_cast<uint8_t>(v >> 8));
}

void PutMac(std::vector<uint8_t>* out, const MacAddress& mac) {
  out->insert(out->end(), mac.bytes.begin(), mac.bytes.end());
}

void PutFcs(std::vector<uint8_t>* out) {
  const uint32_t fcs = Crc32(*out);
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<uint8_t>(fcs >> (8 * i)));
}

}  // namespace

uint32_t Crc32(std::span<const uint8_t> bytes) {
  static const std::array<uint32_t, 256> table = MakeCrcTable();
  uint32_t c = 0xFFFFFFFFu;
  for (uint8_t b : bytes) c = table[(c ^ b) & 0xff] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void BuildDataMpdu(const MacAddress& ra, const MacAddress& ta, uint16_t duration_us,
                   uint16_t sequence_number, bool retry, std::span<const uint8_t> ethernet_frame,
                   std::vector<uint8_t>* out, bool qos, uint8_t tid) {
  out->clear();
  out->reserve(ethernet_frame.size() + 24);
  out->push_back(qos ? 0x88 : 0x08);    // Type data, subtype 0 (Data) or 8 (QoS Data).
  out->push_back(retry ? 0x08 : 0x00);  // Flags: Retry bit (9.2.4.1.1).
  Put16(out, duration_us);
  PutMac(out, ra);
  PutMac(out, ta);
  PutMac(out, kBssid);
  Put16(out, static_cast<uint16_t>((sequence_number & 0x0fff) << 4));
  if (qos) Put16(out, tid & 0x0f);  // QoS Control: TID, normal ack, no A-MSDU (9.2.4.5).
  // RFC 1042 LLC/SNAP, then the Ethernet type and payload.
  for (uint8_t b : {0xAA, 0xAA, 0x03, 0x00, 0x00, 0x00}) out->push_back(b);
  out->insert(out->end(), ethernet_frame.begin() + 12, ethernet_frame.end());
  PutFcs(out);
}

void BuildControlMpdu(FrameKind kind, const MacAddress& ra, const MacAddress& ta,
                      uint16_t duration_us, std::vector<uint8_t>* out) {
  out->clear();
  // Control subtypes (9.2.4.1.3): RTS 11, CTS 12, ACK 13, CF-End 14.
  const uint8_t fc0 = kind == FrameKind::kAck   ? 0xD4
                      : kind == FrameKind::kCts ? 0xC4
                      : kind == FrameKind::kRts ? 0xB4
                                                : 0xE4;
  out->push_back(fc0);
  out->push_back(0x00);
  Put16(out, duration_us);
  PutMac(out, ra);
  if (kind == FrameKind::kRts) PutMac(out, ta);
  if (kind == FrameKind::kCfEnd) PutMac(out, kBssid);  // 9.3.1.9: the BSSID (TA).
  PutFcs(out);
}

std::vector<uint8_t> MpduBytes(const TxRecord& tx) {
  std::vector<uint8_t> mpdu;
  if (tx.kind == FrameKind::kData) {
    SITLNET_DEMAND(tx.ethernet_frame != nullptr && tx.ethernet_frame->size() >= 14);
    BuildDataMpdu(tx.receiver, tx.transmitter, tx.duration_us, tx.sequence_number, tx.retry,
                  *tx.ethernet_frame, &mpdu, tx.qos, tx.tid);
  } else {
    BuildControlMpdu(tx.kind, tx.receiver, tx.transmitter, tx.duration_us, &mpdu);
  }
  return mpdu;
}

}  // namespace sitlnet::mac
