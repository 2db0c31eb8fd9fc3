// 802.11ac Block Ack agreements without A-MPDU (block_ack.cc's NeedSetupBlockAck and
// UsesBlockAck). ns-3 3.37 sets up an agreement for every VHT station whatever its
// *_MaxAmpduSize says (HtFrameExchangeManager::NeedSetupBlockAck, ht-frame-exchange-manager.cc
// lines 127-131 at ns-3.37: GetVhtSupported()); 802.11n needs a non-zero A-MPDU limit. Under
// the agreement a single MPDU whose sequence number starts the window goes with a normal ACK
// (WifiDefaultAckManager::TryAddMpdu); an MPDU given up owes a BlockAckReq that moves the
// recipient's window (BlockAckManager::NotifyDiscardedMpdu), a SIFS after the ACK if it expired
// in flight (frame_exchange.cc's WipesAtEveryArrival). docs/mac_phy_sim.md, "A-MPDU and Block
// Ack", has the whole account.
#include <gtest/gtest.h>

#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::MakeEthernetFrame;

const MacAddress kA{{2, 0, 0, 0, 0, 1}}, kB{{2, 0, 0, 0, 0, 2}};

// Two payload bytes past the IPv4 header carry the frame's index, to check the order of
// delivery; byte 15 (the DS byte) sets the user priority.
constexpr size_t kIndexByte = 40;
std::vector<uint8_t> NumberedFrame(int index, int user_priority = 0) {
  std::vector<uint8_t> frame = MakeEthernetFrame(kB, kA, 1500);
  frame[15] = static_cast<uint8_t>(user_priority << 5);
  frame[kIndexByte] = static_cast<uint8_t>(index >> 8);
  frame[kIndexByte + 1] = static_cast<uint8_t>(index);
  return frame;
}
int IndexOf(const Delivery& d) {
  return d.ethernet_frame[kIndexByte] << 8 | d.ethernet_frame[kIndexByte + 1];
}

// VHT MCS 4, 80 MHz at this distance: about half the MPDUs lost (log-distance, exponent 3;
// the error rate climbs from nought at 21 m to all at 25 m).
constexpr double kLossyDistanceM = 23.5;

// VHT MCS 0, 80 MHz, A-MPDU off (radio.aggregation false, its default).
MediumConfig Vht() {
  MediumConfig config;
  config.standard = Standard::k80211ac;
  config.mcs = 0;
  config.channel_width_mhz = 80;
  return config;
}

// A sends B `frames` frames of user priority `up` at time 0, B `distance_m` away; the trace.
std::vector<TraceEvent> RunPair(const MediumConfig& config, int frames, double distance_m,
                                TimeNs until_ns, std::vector<Delivery>* deliveries, int up = 0) {
  Medium medium(config);
  medium.EnableTrace(true);
  medium.AddStation(kA, {0, 0, 0});
  medium.AddStation(kB, {distance_m, 0, 0});
  for (int i = 0; i < frames; ++i) medium.SubmitFrame(0, NumberedFrame(i, up), 0);
  medium.AdvanceTo(until_ns, deliveries);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  return trace;
}

std::vector<TxRecord> Transmissions(const std::vector<TraceEvent>& trace) {
  std::vector<TxRecord> txs;
  for (const TraceEvent& e : trace) {
    if (e.tx) txs.push_back(*e.tx);
  }
  return txs;
}

// The exchange ns-3 3.37 runs for an 802.11ac pair without A-MPDU: first the ADDBA Request
// and its ACK; the Response (when B wins the channel) and its ACK; each data frame alone (an
// S-MPDU, no A-MPDU reference) with a normal ACK, numbered 0, 1, 2, ... for the receiver; no
// BlockAck. Also for voice, whose A-MPDU limit is 0 even with aggregation on (ns-3's
// VO_MaxAmpduSize); its TXOP may end with a CF-End.
TEST(VhtAgreementTest, AnAcPairWithoutAmpduSetsUpAnAgreementAndAcksSingleMpdus) {
  MediumConfig voice = Vht();
  voice.aggregation = true;
  for (const auto& [config, up] : {std::pair{Vht(), 0}, std::pair{voice, 6}}) {
    SCOPED_TRACE(up);
    constexpr int kFrames = 10;
    std::vector<Delivery> deliveries;
    std::vector<TxRecord> txs;
    for (const TxRecord& t :
         Transmissions(RunPair(config, kFrames, 1, 50 * kNsPerMs, &deliveries, up))) {
      if (t.kind != FrameKind::kCfEnd) txs.push_back(t);
    }
    ASSERT_EQ(txs.size(), 4u + 2 * kFrames);
    EXPECT_EQ(txs[0].kind, FrameKind::kAction);
    EXPECT_FALSE(txs[0].addba_response);
    EXPECT_EQ(txs[0].source, 0);
    EXPECT_EQ(txs[0].rate_mbps, 6);  // The lowest basic rate (GetDataTxVector, management).
    int responses = 0, next_sequence = 0;
    for (size_t i = 0; i < txs.size(); i += 2) {
      const TxRecord& t = txs[i];
      EXPECT_EQ(txs[i + 1].kind, FrameKind::kAck) << i;  // Every frame has its ACK next.
      if (t.kind == FrameKind::kAction) {
        responses += t.addba_response && t.source == 1;
        continue;
      }
      ASSERT_EQ(t.kind, FrameKind::kData) << i;
      EXPECT_TRUE(t.vht);
      EXPECT_EQ(t.tid, up);
      EXPECT_FALSE(t.ampdu_reference.has_value());
      EXPECT_FALSE(t.retry);
      EXPECT_EQ(t.sequence_number, next_sequence++);
    }
    EXPECT_EQ(responses, 1);
    ASSERT_EQ(deliveries.size(), static_cast<size_t>(kFrames));
    for (int i = 0; i < kFrames; ++i) EXPECT_EQ(IndexOf(deliveries[static_cast<size_t>(i)]), i);
  }
}

// 802.11n without A-MPDU sets up none (ns-3: the A-MPDU limit must be non-zero): data and ACKs.
TEST(VhtAgreementTest, An80211nPairWithoutAmpduSetsUpNone) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  config.mcs = 7;
  std::vector<Delivery> deliveries;
  for (const TxRecord& t : Transmissions(RunPair(config, 10, 1, 20 * kNsPerMs, &deliveries))) {
    EXPECT_TRUE(t.kind == FrameKind::kData || t.kind == FrameKind::kAck);
  }
  EXPECT_EQ(deliveries.size(), 10u);
}

// On a lossy link under the agreement, as ns-3 3.37: a missed ACK brings a retransmission of
// the same MPDU (Retry set), up to the retry limit (NormalAckTimeout, NeedRetransmission), and no
// BlockAckReq; an MPDU given up at the limit or by its lifetime owes a BlockAckReq
// (NotifyDiscardedMpdu), the next exchange, answered by a BlockAck, which moves the recipient's
// window past it. Frames that expire unsent leave no gap in the numbers (given at first send).
// So every frame is delivered once, in order, or dropped: none waits behind a hole.
TEST(VhtAgreementTest, AnMpduGivenUpBringsABlockAckReqThatMovesTheRecipientsWindow) {
  MediumConfig config = Vht();
  config.mcs = 4;
  config.short_retry_limit = 2;
  config.queue_max_delay_ns = 40 * kNsPerMs;
  constexpr int kFrames = 300;
  std::vector<Delivery> deliveries;
  const std::vector<TraceEvent> trace =
      RunPair(config, kFrames, kLossyDistanceM, 400 * kNsPerMs, &deliveries);
  size_t limit_drops = 0, expired = 0, data_dropped = 0, bars = 0, bars_answered = 0;
  TimeNs first_limit_drop_ns = -1, first_bar_ns = -1;
  const std::vector<TxRecord> txs = Transmissions(trace);
  for (const TraceEvent& e : trace) {
    if (!e.drop || e.drop->ethernet_bytes == 0) continue;  // Action frames carry none.
    ++data_dropped;
    expired += e.drop->reason == DropReason::kQueueExpired;
    if (e.drop->reason == DropReason::kRetryLimit && limit_drops++ == 0) {
      first_limit_drop_ns = e.drop->time_ns;
    }
  }
  const TxRecord* last_data = nullptr;
  for (size_t i = 0; i < txs.size(); ++i) {
    const TxRecord& t = txs[i];
    if (t.kind == FrameKind::kData) {
      EXPECT_FALSE(t.ampdu_reference.has_value());
    }
    if (t.kind == FrameKind::kData && t.source == 0) {
      if (t.retry) {
        ASSERT_NE(last_data, nullptr);
        EXPECT_EQ(t.sequence_number, last_data->sequence_number);
      }
      last_data = &t;
    }
    if (t.kind != FrameKind::kBlockAckReq) continue;
    if (bars++ == 0) first_bar_ns = t.start_ns;
    if (i + 1 < txs.size() && txs[i + 1].kind == FrameKind::kBlockAck &&
        txs[i + 1].start_ns == t.end_ns + 16 * kNsPerUs) {
      ++bars_answered;
    }
  }
  EXPECT_GT(limit_drops, 5u);
  EXPECT_GT(expired, 5u);
  EXPECT_GT(bars_answered, 5u);
  EXPECT_GT(first_bar_ns, first_limit_drop_ns);
  EXPECT_GT(deliveries.size(), 20u);
  EXPECT_EQ(deliveries.size() + data_dropped, static_cast<size_t>(kFrames));
  int last = -1;
  for (const Delivery& d : deliveries) {
    EXPECT_GT(IndexOf(d), last);
    last = IndexOf(d);
  }
}

// A frame arriving makes an ns-3 3.37 QoS station wipe its expired frames (Txop::Queue asks
// QosTxop::HasFramesToTransmit, which wipes), the MPDU in flight included; that MPDU owes a
// BlockAckReq (NotifyDiscardedMpdu), which goes a SIFS after its ACK with a TXOP limit of 0
// (HtFrameExchangeManager::TransmissionSucceeded). Here a frame arrives every 100 us and lives
// 3 ms, so many are sent at the edge of their lifetime and expire in flight.
TEST(VhtAgreementTest, AnMpduExpiringInFlightBringsABlockAckReqASifsAfterItsAck) {
  MediumConfig config = Vht();
  config.queue_max_delay_ns = 3 * kNsPerMs;
  Medium medium(config);
  medium.EnableTrace(true);
  medium.AddStation(kA, {0, 0, 0});
  medium.AddStation(kB, {1, 0, 0});
  std::vector<Delivery> deliveries;
  int submitted = 0;
  for (TimeNs t = 0; t < 100 * kNsPerMs; t += 100 * kNsPerUs) {
    medium.SubmitFrame(0, NumberedFrame(submitted++), t);
    medium.AdvanceTo(t + 100 * kNsPerUs - 1, &deliveries);
  }
  medium.AdvanceTo(120 * kNsPerMs, &deliveries);
  std::vector<TraceEvent> trace;
  medium.DrainTrace(&trace);
  const std::vector<TxRecord> txs = Transmissions(trace);
  size_t after_ack = 0, answered = 0, data_dropped = 0;
  for (size_t i = 1; i + 1 < txs.size(); ++i) {
    const TxRecord& ack = txs[i - 1];
    if (txs[i].kind != FrameKind::kBlockAckReq || ack.kind != FrameKind::kAck ||
        !(ack.receiver == kA) || txs[i].start_ns != ack.end_ns + 16 * kNsPerUs) {
      continue;
    }
    ++after_ack;
    answered += txs[i + 1].kind == FrameKind::kBlockAck;
  }
  for (const TraceEvent& e : trace) data_dropped += e.drop && e.drop->ethernet_bytes > 0;
  EXPECT_GT(after_ack, 10u);
  EXPECT_EQ(answered, after_ack);
  EXPECT_EQ(deliveries.size() + data_dropped, static_cast<size_t>(submitted));
  int last = -1;
  for (const Delivery& d : deliveries) {
    EXPECT_GT(IndexOf(d), last);
    last = IndexOf(d);
  }
}

}  // namespace
}  // namespace sitlnet::mac
