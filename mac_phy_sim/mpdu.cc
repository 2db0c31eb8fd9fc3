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

void BuildBlockAckMpdu(FrameKind kind, const MacAddress& ra, const MacAddress& ta,
                       uint16_t duration_us, uint8_t tid, uint16_t starting_sequence,
                       uint64_t bitmap, std::vector<uint8_t>* out) {
  out->clear();
  out->push_back(kind == FrameKind::kBlockAck ? 0x94 : 0x84);  // Subtype 9 BA, 8 BAR.
  out->push_back(0x00);
  Put16(out, duration_us);
  PutMac(out, ra);
  PutMac(out, ta);
  // BA/BAR Control (9.3.1.8.1): immediate ack policy 0, compressed bitmap (bit 2), TID in 12-15.
  Put16(out, static_cast<uint16_t>(0x0004 | (tid & 0x0f) << 12));
  Put16(out, static_cast<uint16_t>((starting_sequence & 0x0fff) << 4));  // Fragment 0.
  if (kind == FrameKind::kBlockAck) {
    for (int i = 0; i < 8; ++i) out->push_back(static_cast<uint8_t>(bitmap >> (8 * i)));
  }
  PutFcs(out);
}

void BuildAddbaMpdu(bool response, const MacAddress& ra, const MacAddress& ta,
                    uint16_t duration_us, uint16_t sequence_number, bool retry, uint8_t tid,
                    uint16_t starting_sequence, std::vector<uint8_t>* out) {
  out->clear();
  out->push_back(0xD0);  // Management, subtype 13: Action.
  out->push_back(retry ? 0x08 : 0x00);
  Put16(out, duration_us);
  PutMac(out, ra);
  PutMac(out, ta);
  PutMac(out, kBssid);
  Put16(out, static_cast<uint16_t>((sequence_number & 0x0fff) << 4));
  out->push_back(3);                 // Category: Block Ack (9.4.1.11).
  out->push_back(response ? 1 : 0);  // ADDBA Request 0, Response 1 (9.6.5.1).
  out->push_back(1);                 // Dialog token.
  if (response) Put16(out, 0);       // Status: success.
  // Block Ack Parameter Set (9.4.1.14): A-MSDU supported, immediate, TID, buffer size 64
  // (ns-3's Request says 0: the recipient chooses).
  const uint16_t buffer = response ? 64 : 0;
  Put16(out, static_cast<uint16_t>(0x0001 | 0x0002 | (tid & 0x0f) << 2 | buffer << 6));
  Put16(out, 0);  // Block Ack Timeout: none.
  if (!response) Put16(out, static_cast<uint16_t>((starting_sequence & 0x0fff) << 4));
  PutFcs(out);
}

std::vector<uint8_t> MpduBytes(const TxRecord& tx) {
  std::vector<uint8_t> mpdu;
  if (tx.kind == FrameKind::kBlockAck || tx.kind == FrameKind::kBlockAckReq) {
    BuildBlockAckMpdu(tx.kind, tx.receiver, tx.transmitter, tx.duration_us, tx.tid,
                      tx.ba_starting_sequence, tx.ba_bitmap, &mpdu);
  } else if (tx.kind == FrameKind::kAction) {
    BuildAddbaMpdu(tx.addba_response, tx.receiver, tx.transmitter, tx.duration_us,
                   tx.sequence_number, tx.retry, tx.tid, tx.ba_starting_sequence, &mpdu);
  } else if (tx.kind == FrameKind::kData) {
    SITLNET_DEMAND(tx.ethernet_frame != nullptr && tx.ethernet_frame->size() >= 14);
    BuildDataMpdu(tx.receiver, tx.transmitter, tx.duration_us, tx.sequence_number, tx.retry,
                  *tx.ethernet_frame, &mpdu, tx.qos, tx.tid);
  } else {
    BuildControlMpdu(tx.kind, tx.receiver, tx.transmitter, tx.duration_us, &mpdu);
  }
  return mpdu;
}

}  // namespace sitlnet::mac
