// 802.11 MPDU bytes for the trace (9.2.4, 9.3): data frames in an IBSS
// (addr1 DA, addr2 SA/TA, addr3 BSSID), LLC/SNAP (RFC 1042) + Ethernet
// payload, control frames (ACK, CTS, RTS), each with its CRC-32 FCS.
#ifndef SITLNET_MAC_PHY_SIM_MPDU_H_
#define SITLNET_MAC_PHY_SIM_MPDU_H_

#include <cstdint>
#include <span>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

// The BSSID all stations share (a locally administered address).
inline constexpr MacAddress kBssid{{0x02, 0x53, 0x4e, 0x45, 0x54, 0x00}};

uint32_t Crc32(std::span<const uint8_t> bytes);  // IEEE 802.3 CRC-32 (reflected).

// Appends the MPDU to *out (cleared first). `qos`: a QoS Data frame (subtype 8) whose QoS
// Control field carries `tid`, normal acknowledgement (9.2.4.5).
void BuildDataMpdu(const MacAddress& ra, const MacAddress& ta, uint16_t duration_us,
                   uint16_t sequence_number, bool retry, std::span<const uint8_t> ethernet_frame,
                   std::vector<uint8_t>* out, bool qos = false, uint8_t tid = 0);
void BuildControlMpdu(FrameKind kind, const MacAddress& ra, const MacAddress& ta,
                      uint16_t duration_us, std::vector<uint8_t>* out);
// Compressed BlockAck (32 B, with `bitmap`) or BlockAckReq (24 B) for `tid` (9.3.1.8-9).
void BuildBlockAckMpdu(FrameKind kind, const MacAddress& ra, const MacAddress& ta,
                       uint16_t duration_us, uint8_t tid, uint16_t starting_sequence,
                       uint64_t bitmap, std::vector<uint8_t>* out);
// ADDBA Request (with `starting_sequence`) or Response, 37 B each (9.6.5.2-3).
void BuildAddbaMpdu(bool response, const MacAddress& ra, const MacAddress& ta,
                    uint16_t duration_us, uint16_t sequence_number, bool retry, uint8_t tid,
                    uint16_t starting_sequence, std::vector<uint8_t>* out);

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_MPDU_H_
