// A-MPDU aggregation and Block Ack (IEEE 802.11-2016 10.12, 10.24; ns-3 3.37's MpduAggregator,
// BlockAckManager and HtFrameExchangeManager): the arithmetic of an A-MPDU's length and its
// subframes' place in the PPDU, and the agreement state of originator and recipient. The frame
// exchange that uses them is in frame_exchange.cc and block_ack.cc; docs/mac_phy_sim.md,
// "A-MPDU and Block Ack", says what is modelled and what is not.
#ifndef SITLNET_MAC_PHY_SIM_BLOCK_ACK_H_
#define SITLNET_MAC_PHY_SIM_BLOCK_ACK_H_

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"

namespace sitlnet::mac {

// The Block Ack window: 64 MPDUs (ns-3 3.37's MpduBufferSize for HT and VHT), so no A-MPDU
// holds more.
inline constexpr int kBlockAckWindow = 64;
inline constexpr int kMaxAmpduSubframes = kBlockAckWindow;
// aPPDUMaxTime, HT and VHT (19.4.4, 21.4.4; ns-3's GetPpduMaxTime): 5484 us.
inline constexpr TimeNs kMaxPpduDurationNs = 5484 * kNsPerUs;
// The largest A-MPDU a station may send: HT 65535 B, VHT 1048575 B (ns-3 caps its
// *_MaxAmpduSize so, MpduAggregator::GetMaxAmpduSize).
inline constexpr uint32_t kMaxAmpduBytesHt = 65535;
inline constexpr uint32_t kMaxAmpduBytesVht = 1048575;
// Frame sizes (FCS included): compressed BlockAck 32 B, compressed BlockAckReq 24 B (9.3.1.8-9);
// ADDBA Request and Response: a 24-byte management header, category and action, 7 bytes of
// body, FCS (9.6.5.2-3; ns-3's MgtAddBaRequestHeader and MgtAddBaResponseHeader).
inline constexpr int kBlockAckBytes = 32;
inline constexpr int kBlockAckReqBytes = 24;
inline constexpr int kAddbaBytes = 37;

// The A-MPDU length after appending an MPDU of `mpdu_bytes` to one of `ampdu_bytes` (0: empty):
// the earlier subframe is padded to a multiple of 4 B, then a 4-byte delimiter and the MPDU
// (9.7.1; ns-3 3.37's MpduAggregator::GetSizeIfAggregated). The last subframe is not padded.
constexpr int AmpduBytesIfAggregated(int ampdu_bytes, int mpdu_bytes) {
  return ampdu_bytes + (4 - ampdu_bytes % 4) % 4 + 4 + mpdu_bytes;
}

// An MPDU of an A-MPDU on the air: what it carries and where its subframe (delimiter first)
// starts in the PSDU.
struct AmpduSubframe {
  std::shared_ptr<const std::vector<uint8_t>> ethernet;
  uint16_t sequence_number = 0;
  bool retry = false;
  int offset_bytes = 0;
};

// The part of the PPDU's payload time that carries subframe `i` of `count` in a PSDU: from its
// first bit to the next subframe's (the first from the payload's start, SERVICE bits included;
// the last to the payload's end, tail and padding included), as ns-3's per-MPDU windows
// (PhyEntity::EndOfMpdu; payload duration pro rata of bits). Offsets from the payload's start.
struct SubframeWindowNs {
  TimeNs begin_ns = 0, end_ns = 0;
};
SubframeWindowNs SubframeWindow(const std::vector<AmpduSubframe>& subframes, int i,
                                double rate_mbps, TimeNs payload_ns);

// The originator's agreement with one recipient for one TID (ns-3's
// OriginatorBlockAckAgreement). Pending from the ADDBA Request until the Response; no reply
// when the Response did not come within 1 ms of the Request's ACK (QosTxop's
// AddBaResponseTimeout) or the Request was discarded; reset 200 ms later (FailedAddBaTimeout),
// when a new Request may go. No inactivity timeout (ns-3's default, 0).
struct BaOriginator {
  enum class Phase : uint8_t { kPending, kEstablished, kNoReply };
  MacAddress recipient;
  uint8_t tid = 0;
  Phase phase = Phase::kPending;
  TimeNs response_deadline_ns = -1;  // Pending with the Request ACKed: no reply after this.
  TimeNs reset_ns = -1;              // No reply: the agreement is gone from this time.
  // A BlockAckReq is owed (ns-3's BlockAckManager::ScheduleBar): after a missed BlockAck, or
  // after an MPDU sent under the agreement was given up. `bar_only_with_data`: send it only
  // when a frame for the recipient and TID is queued (ns-3's skipIfNoDataQueued).
  bool bar_pending = false;
  bool bar_only_with_data = false;
  // The BlockAckReq owed is the last one again, its BlockAck missed with MPDUs in flight:
  // sent with the Retry bit (ns-3's MissedBlockAck sets it).
  bool bar_retry = false;
};

// The recipient's agreement with one originator for one TID (ns-3's
// RecipientBlockAckAgreement): the reordering buffer of the window [window_start,
// window_start + 64) (WinStartB, 10.24.7.6): MPDUs are delivered in sequence-number order; a
// received MPDU beyond the window, or a BlockAckReq, moves it on and delivers what it passes
// over. Beside it the scoreboard a BlockAck reports (WinStartR, 10.24.7.3): it moves only when
// an MPDU beyond its end or a BlockAckReq comes, so it still shows the MPDUs delivered.
struct BaRecipient {
  struct Buffered {
    std::shared_ptr<const std::vector<uint8_t>> ethernet;
    double power_dbm = 0, sinr = 0;
  };
  int originator = 0;  // Station id.
  uint8_t tid = 0;
  uint16_t window_start = 0;
  uint64_t received = 0;  // Bit k: window_start + k is buffered.
  std::array<Buffered, kBlockAckWindow> buffer;  // By sequence number mod 64.
  uint16_t scoreboard_start = 0;  // WinStartR.
  uint64_t scoreboard = 0;        // Bit k: scoreboard_start + k was received.
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_BLOCK_ACK_H_
