// Internal state of a Medium and the stages that act on it. The stages are
// split by responsibility (ns-3's decomposition, without its object system):
//   channel_access.cc  CCA busy/idle, NAV, IFS, backoff countdown (DCF, EDCA)
//   frame_exchange.cc  queues, DATA/ACK, RTS/CTS, TXOPs, timeouts, retries, duplicates
//   ampdu_exchange.cc  A-MPDU/BlockAck, BlockAckReq and ADDBA exchanges (802.11n/ac)
//   block_ack.cc       Block Ack agreements and the recipient's reordering buffer
//   reception.cc       PHY: signal arrival, preamble lock, interference/SINR
//                      chunks, error-rate draw at the end
//   transmission.cc    putting a PPDU on the air and taking it off (+ trace)
//   medium.cc          the public API and the event loop
#ifndef SITLNET_MAC_PHY_SIM_MEDIUM_STATE_H_
#define SITLNET_MAC_PHY_SIM_MEDIUM_STATE_H_

#include <array>
#include <deque>
#include <memory>
#include <optional>
#include <random>
#include <vector>

#include "mac_phy_sim/channel.h"
#include "mac_phy_sim/block_ack.h"
#include "mac_phy_sim/gamma.h"
#include "mac_phy_sim/jakes_doppler.h"
#include "mac_phy_sim/jakes_fading.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/rate_manager.h"
#include "mac_phy_sim/scheduler.h"

namespace sitlnet::mac {

using Bytes = std::shared_ptr<const std::vector<uint8_t>>;

// With fading, links whose mean power is more than this under the RX
// sensitivity are never received: a Gamma(m, 1/m) gain exceeds +16 dB
// (39.8 x the mean) with probability erfc(sqrt(19.9)) = 2.5e-10 for the
// smallest m allowed (0.5, where the gain is a squared normal), less for
// larger m. Links that far under in free space are not drawn at all.
inline constexpr double kFadingMarginDb = 16;

// ns-3 ConstantSpeedPropagationDelayModel's default speed; also the wavelength's.
inline constexpr double kSpeedOfLightMps = 299792458.0;

// ns-3's PreambleDetectionDuration: 4 us after a frame starts at a station,
// the preamble detection model decides whether it locks on; only then does
// its PHY report the medium busy (PhyEntity::EndPreambleDetectionPeriod ->
// NotifyCcaBusy, or DropPreambleEvent -> SwitchMaybeToCcaBusy on energy).
// The OFDM PHY's aCCATime (IEEE 802.11-2016 Clause 17) is the same 4 us.
inline constexpr TimeNs kPreambleDetectionNs = 4 * kNsPerUs;

// A PHY mode with its PHY header, the SINRs above which the error rates
// of payload and header are exactly zero, and the receiver noise for it.
struct ModeEntry {
  PhyMode mode;
  double perfect_sinr = 0;
  PhyHeader header;
  double header_perfect_sinr = 0;
  // mW: a/b/g the one noise floor (PhyInfo); n/ac over the PPDU's measurement width (a 20 MHz
  // ACK sees half the noise of a 40 MHz data frame, as in ns-3).
  double noise_mw = 0;
};

// A data rate: its mode, the mode of the control responses to it (ACK, CTS;
// also RTS frames sent ahead of it), their airtimes, and ns-3
// IdealWifiManager's SNR threshold for it (linear).
struct RateEntry {
  ModeEntry data;
  ModeEntry control;
  TimeNs ack_ns = 0, cts_ns = 0;
  double ideal_snr_threshold = 0;
  bool basic = false;  // In the basic rate set (phy_mode.h).
};

// What a queued MPDU is: a QoS Data frame carrying an MSDU, or a Block Ack action frame
// (ns-3 queues those in the TID's access category, at the head).
enum class MpduType : uint8_t { kData, kAddbaRequest, kAddbaResponse };

// An MSDU in a station's queue or in service.
struct QueuedFrame {
  MpduType type = MpduType::kData;
  bool sequence_assigned = false;  // Kept when the frame goes back to the queue (Block Ack).
  uint16_t ba_ssn = 0;             // ADDBA Request: the agreement's starting sequence number.
  Bytes ethernet;
  MacAddress destination;
  bool group = false;
  uint8_t tid = 0;  // QoS stations: the user priority (QoS Control); DCF: 0.
  uint16_t sequence_number = 0;
  TimeNs enqueued_ns = 0;         // For queue_max_delay_ns.
  bool data_sent_before = false;  // Sets the Retry bit.
  // Sent and not yet reported lost: in ns-3's BlockAckManager in-flight list, which a missed
  // BlockAck keeps and a BlockAck or missed ACK that reports it lost leaves (TO_RETRANSMIT).
  bool in_flight = false;
  bool use_rts = false;
  // With aggregation: the A-MPDU the current attempt plans (PlannedAmpduBytes), whose length
  // decides use_rts and whose airtime the RTS's Duration covers; 0: a single MPDU.
  int ampdu_bytes = 0;
  const RateEntry* rate = nullptr;      // DATA rate of the current attempt (rate_control.cc).
  const RateEntry* rts_rate = nullptr;  // Times the CTS answering the current attempt's RTS.
  const ModeEntry* rts_mode = nullptr;  // Mode of the current attempt's RTS.
};

// What one receiver saw of one transmission.
struct RxEntry {
  int station = 0;
  double power_mw = 0;
  double power_dbm = 0;
  RxOutcome outcome = RxOutcome::kBelowSensitivity;
  double sinr = 0;      // Linear: lowest SINR of a locked frame, else SNR (dB only on output).
  TimeNs delay_ns = 0;  // Propagation delay: the signal spans [start, end] + delay_ns here.
  // Set where the outcome is; interferer and losses only with record_causes.
  RxCause cause = RxCause::kBelowThreshold;
  int interferer = -1;
  float path_loss_db = 0, obstacle_loss_db = 0;
};

// A PPDU on the air.
struct Transmission {
  int id = 0;
  int source = 0;
  FrameKind kind = FrameKind::kData;
  TimeNs start_ns = 0, end_ns = 0;
  const ModeEntry* mode = nullptr;
  bool retry = false;
  bool group = false;
  uint8_t tid = 0;  // QoS Data frames.
  uint16_t sequence_number = 0;
  uint16_t duration_us = 0;
  MacAddress ra, ta;
  double reported_snr = 0;  // ACK/CTS: SNR (linear) of the frame answered, as ns-3's SnrTag.
  Bytes ethernet;           // DATA only.
  // An A-MPDU's MPDUs (empty for any other PPDU; block_ack.h), their outcome at the addressed
  // receiver, and its reference number for the trace.
  std::vector<AmpduSubframe> subframes;
  std::vector<RxOutcome> subframe_outcome;
  uint32_t ampdu_reference = 0;
  bool addba_response = false;  // kAction.
  uint16_t ba_ssn = 0;          // ADDBA Request, BlockAckReq, BlockAck: starting sequence number.
  uint64_t ba_bitmap = 0;       // kBlockAck; its starting sequence number is sequence_number.
  std::vector<RxEntry> rx;  // Receivers above sensitivity, by station id.
  int signals_pending = 0;  // Delayed receivers whose signal has not ended yet.
  bool on_air = false;      // Between StartTransmission and OnTxEnd.
};

// The frame a station's PHY is locked on, with its SINR history so far.
struct Reception {
  int tx = -1;  // Transmission id, -1 when not receiving.
  int entry = 0;
  double power_mw = 0;
  TimeNs start_ns = 0, chunk_start_ns = 0;
  double interference_mw = 0;
  double success_probability = 1;  // Of the whole frame; of its PHY header for an A-MPDU.
  std::array<double, kMaxAmpduSubframes> subframe_success{};  // An A-MPDU's MPDUs.
  double min_sinr = 0;
  bool interfered = false;
  // With record_causes: source and power of the strongest overlapping signal.
  int interferer = -1;
  double interferer_mw = 0;
};

// A signal on the air at a station (record_causes only): transmission id, entry.
struct ActiveSignal {
  int tx = 0;
  int entry = 0;
};

// kWaitBlockAck: after an A-MPDU or a BlockAckReq.
enum class Exchange : uint8_t { kIdle, kWaitAck, kWaitCts, kWaitBlockAck };

// One channel access function: the DCF, or an EDCAF of one access category. Its own queue
// (ns-3 3.37 keeps one WifiMacQueue per access category), contention window, retry counts and
// backoff; the medium's state (busy, NAV, EIFS) is the station's.
struct AccessFunction {
  std::deque<QueuedFrame> queue;  // Waiting frames.
  bool has_current = false;
  QueuedFrame current;  // The frame in service.
  int cw = 0;
  // Retry counts, SRC and LRC (IEEE 802.11-2016 10.3.4.4; QSRC/QLRC per access category,
  // 10.22.2.11; ns-3's per-AC SSRC/SLRC): they count failures until a success or a discard,
  // across frames, so a frame that expired in the queue passes its count on to the next one.
  int short_retry_count = 0, long_retry_count = 0;
  bool backoff_pending = false;   // Counting down (for a frame, or post-backoff).
  bool immediate_access = false;  // Pending access without a drawn backoff (10.3.4.2).
  int backoff_slots = 0;
  TimeNs backoff_start_ns = 0;
  TimeNs count_origin_ns = 0;  // Where slot counting starts for the scheduled access.
  TimeNs access_at_ns = -1;    // Scheduled access, -1 if none (State::SetAccessAt).
  TimeNs txop_start_ns = -1;   // Start of the TXOP it holds (10.22.2.8), -1 if none.
  // Block Ack (block_ack.h): the MPDUs of the A-MPDU under way after `current` (empty outside
  // an A-MPDU's exchange). They count against the queue's limit (ns-3 keeps in-flight MPDUs in
  // its WifiMacQueue).
  std::vector<QueuedFrame> ampdu_rest;
};

// The next QoS Data sequence number per TID for one receiver (ns-3's MacTxMiddle).
struct ReceiverSequences {
  MacAddress receiver;
  std::array<uint16_t, 8> next{};
};

struct StationState {
  MacAddress mac;
  double tx_power_dbm = 0, tx_power_mw = 0;
  const RateEntry* rate = nullptr;  // Its constant data rate.
  std::unique_ptr<RateManager> rate_manager;  // Chooses its unicast rates (rate_manager.h).
  std::mt19937_64 rng;
  // Only drawn from with nakagami_fading (runs without it unchanged); its own
  // generator, cheaper than rng's (gamma.h).
  RandomEngine fading_rng;
  // Fading: squared distance beyond which this station's signal is more than
  // State::fading_margin_db under the sensitivity on path loss alone (never drawn).
  double fading_reach_m2 = 0;
  StationCounters counters;
  int exchange_ac = 0;  // The access category whose frame exchange is under way.
  // Bit ac set while acs[ac].backoff_pending: the loops over access functions visit only these
  // (a DCF station has at most one), so the DCF costs what it did before EDCA.
  uint8_t pending_mask = 0;
  // Next sequence number per TID, across receivers: the numbering without Block Ack
  // (UsesBlockAck false: a/b/g, 802.11n without aggregation), kept so that those runs keep
  // their bytes (aggregation_off_golden_test.cc); a receiver without a Block Ack agreement only
  // compares a frame's number with the last one's.
  std::array<uint16_t, 8> next_sequence_number{};
  // With Block Ack: per receiver and TID, as ns-3's MacTxMiddle, so that a recipient's
  // reordering buffer sees no gaps; given when an MPDU is first sent, as ns-3 does, so that
  // a frame that expires unsent leaves none either.
  std::vector<ReceiverSequences> receiver_sequences;
  uint16_t next_management_sequence = 0;  // Action frames' own counter (ns-3's non-QoS one).
  // Block Ack agreements (block_ack.h) as originator and as recipient; few, searched linearly.
  std::vector<BaOriginator> ba_originator;
  std::vector<BaRecipient> ba_recipient;
  uint32_t next_ampdu_reference = 0;
  std::vector<AmpduSubframe> ampdu_staging;  // Reused: the next A-MPDU's subframes.
  // The agreement a BlockAck is awaited for (Exchange::kWaitBlockAck), and whether it answers
  // a BlockAckReq (else an A-MPDU).
  MacAddress block_ack_recipient;
  uint8_t block_ack_tid = 0;
  bool block_ack_after_bar = false;
  // Channel access (DCF and EDCA alike).
  bool busy = false;
  TimeNs idle_since_ns = 0;
  bool use_eifs = false;       // Last reception failed (10.3.2.3.7).
  TimeNs access_at_ns = -1;    // Earliest access over the access functions, -1 if none.
  TimeNs nav_event_ns = -1;    // Pending kNavEnd event time, -1 if none.
  TimeNs nav_until_ns = 0;
  // End of the last ACK/CTS timeout: from when it starts (ns-3's NotifyAckTimeoutStartNow)
  // until the response ends it; no access function counts its AIFS before it.
  TimeNs timeout_end_ns = -kNsPerS;
  // PHY.
  int transmitting_tx = -1;
  int active_signals = 0;
  double energy_mw = 0;
  Reception rx;
  std::vector<ActiveSignal> active;  // Maintained only with record_causes.
  // Frame exchange.
  Exchange exchange = Exchange::kIdle;
  uint64_t timeout_generation = 0;
  bool timeout_waits_for_rx = false;
  bool response_pending = false;
  FrameKind response_kind = FrameKind::kAck;
  MacAddress response_ra;
  uint16_t response_duration_us = 0;
  const RateEntry* response_rate = nullptr;  // Rate of the frame being answered.
  double response_snr = 0;
  uint8_t response_tid = 0;
  int response_source = 0;
  // Last sequence number per source station and TID (index source * 8 + tid), -1: none.
  std::vector<int> last_sequence_from;
  // One channel access function per access category (EDCAF, 10.22.2), indexed by
  // AccessCategory; a DCF station uses only best effort's (PhyInfo::edca). Last: large and
  // mostly idle, kept after the fields every frame touches.
  std::array<AccessFunction, kAccessCategoryCount> acs;
};

struct PendingMove {
  int station = 0;
  Vec3d position_m;
};

struct PendingFrame {
  int station = 0;
  Bytes ethernet;
};

struct Medium::State {
  State(const MediumConfig& config, const PhyInfo& phy);

  MediumConfig config;
  PhyInfo phy;
  std::vector<RateEntry> rates;  // Every rate of the standard, ascending; never resized.
  const RateEntry* group_rate = nullptr;
  double max_tx_power_dbm = 0;  // Over the config and every station.
  double noise_mw = 0, cca_mw = 0, preamble_snr_linear = 0;
  // Nakagami fading: Gamma(m, 1) samplers for m0, m1, m2 (stateless: the
  // stream is the transmitter's fading_rng).
  GammaSampler fading[3];
  // Jakes fading: the pairs' processes (set only with jakes_fading).
  std::optional<JakesFading> jakes;
  // With jakes_doppler_from_speed: the stations' speeds and the pairs' Doppler phases.
  std::optional<SpeedDoppler> speed_doppler;
  // The largest gain fading can give a frame, in dB: kFadingMarginDb with Nakagami (a bound
  // exceeded with probability <= 2.5e-10), 10 log10(2 M) with Jakes (exact), else 0. Links
  // weaker on average than the sensitivity by more are never received.
  double fading_margin_db = 0;

  RadioChannel channel;
  Scheduler scheduler;
  TimeNs now_ns = 0;
  std::vector<StationState> stations;
  std::vector<Transmission> transmissions;  // Pool, indexed by id.
  std::vector<int> free_transmissions;
  std::vector<PendingFrame> pending_frames;
  std::vector<int> free_pending_frames;
  std::vector<PendingMove> pending_moves;
  std::vector<int> free_pending_moves;

  // Earliest scheduled access over all stations (ties: lowest station id);
  // recomputed by a scan only when the cached one is moved or removed.
  bool earliest_access_valid = true;
  TimeNs earliest_access_ns = -1;
  int earliest_access_station = -1;
  // Sets the scheduled access of access function `ac` of `station` (-1: none).
  void SetAccessAt(int station, int ac, TimeNs at_ns);
  void EarliestAccess(TimeNs* at_ns, int* station);

  bool trace_enabled = false;
  bool record_causes = false;  // Fill RxEntry's interferer and losses (EnableCauses).
  std::vector<TraceEvent> trace;
  std::vector<Delivery>* deliveries = nullptr;  // Set during AdvanceTo.
};

using State = Medium::State;

// ---- channel_access.cc
void UpdateCca(State& s, int station);
void RequestAccess(State& s, int station, int ac);  // A frame became current.
void StartBackoff(State& s, int station, int ac);   // Draw from CW and count down.
// Re-times every counting access function (an ACK/CTS timeout started).
void RescheduleAccess(State& s, int station);
void OnAccess(State& s, int station);  // One or more of its access functions' time is now.
void SetNav(State& s, int station, TimeNs until_ns);
int DrawUniform(StationState& st, int max_inclusive);
// The access category a frame of `tid` goes in: its own on QoS stations, best effort (the
// DCF) otherwise.
int AccessFunctionFor(const State& s, int tid);

// ---- frame_exchange.cc
void OnEnqueue(State& s, int station, Bytes ethernet);
// Backoff of `ac` done: RTS or DATA. False if it had nothing left to send (every frame expired).
bool StartCurrentFrame(State& s, int station, int ac);
// `ac` lost an internal collision to a higher access category of its station (10.22.2.11.2).
void OnInternalCollision(State& s, int station, int ac);
// A SIFS after a successful exchange within the TXOP of `ac`: its next frame, or a CF-End.
void OnContinueTxop(State& s, int station, int ac);
void OnOwnTxEnd(State& s, const Transmission& tx);  // MAC side of a finished PPDU.
void OnFrameReceived(State& s, int station, const Transmission& tx, const RxEntry& entry);
void OnLockedRxEnd(State& s, int station);  // Resolves a deferred timeout.
void OnTimeout(State& s, int station, uint64_t generation);
void OnRespond(State& s, int station);
// Shared with ampdu_exchange.cc.
// The Duration field's microseconds for `ns`, rounded up.
uint16_t DurationFieldUs(TimeNs ns);
// The MPDU length of a queued frame (a QoS Data frame or an action frame), FCS included.
int DataMpduBytes(const State& s, const QueuedFrame& frame);
// What is left of the TXOP access function `f` (category `ac`) holds, >= 0.
TimeNs RemainingTxopNs(const State& s, const AccessFunction& f, int ac);
// Gives `f` its sequence number if it has none yet (per receiver and TID with UsesBlockAck).
void AssignSequence(State& s, int station, QueuedFrame& f);
// The number the next QoS Data frame to `receiver` for `tid` will get (not taken).
uint16_t PeekSequence(State& s, int station, const MacAddress& receiver, int tid);
// Takes the next queued frame of `ac` into service, if any.
void NextFrame(State& s, int station, int ac);
// The frame exchange of the frame in service succeeded (`current_done` false: it stays in
// service): the TXOP goes on a SIFS later if time is left, else the channel is released.
void ExchangeSucceeded(State& s, int station, bool current_done = true);
// A response (`kind`) to send a SIFS from now to `ra`, answering a frame at rate `answered`.
void ScheduleResponse(State& s, int station, FrameKind kind, const MacAddress& ra,
                      uint16_t duration_us, const RateEntry* answered = nullptr, double snr = 0);
// A drop in the trace; `sequence_number` empty for a frame never given one.
void TraceDrop(State& s, int station, DropReason reason, const MacAddress& destination,
               std::optional<uint16_t> sequence_number, size_t bytes);
// The sequence number of `f`, if it was given one.
std::optional<uint16_t> SequenceNumberOf(const QueuedFrame& f);
// Removes the frames of `ac` that waited longer than queue_max_delay_ns (ns-3's
// WifiMacQueue::WipeAllExpiredMpdus), the one in service too if `include_current`.
void DropExpired(State& s, int station, int ac, bool include_current);

// ---- ampdu_exchange.cc
// Before the frame in service of `ac`: a BlockAckReq owed by one of its agreements (true:
// sent), or an ADDBA Request put in service ahead of the frame (false: send the frame in
// service, now the Request). `available_ns`: what is left of the TXOP when the exchange does
// not start it, which the BlockAckReq's exchange must fit in; -1: no limit.
bool PrepareBlockAckExchange(State& s, int station, int ac, TimeNs available_ns = -1);
// A BlockAckReq is owed by an agreement of `ac`: the category contends even with no frame.
bool HasBlockAckReqToSend(State& s, int station, int ac);
// The frame in service goes with others for the same receiver and TID as an A-MPDU, if it is
// under an agreement and any other fits (true: sent).
bool TrySendAmpdu(State& s, int station);
// The PSDU length of the A-MPDU TrySendAmpdu would send now for the frame in service (its rates
// chosen), nothing taken from the queue; 0 if it would go alone. An A-MPDU longer than
// rts_threshold_bytes leaves `rts_protection_ns` (RTS, CTS, 2 SIFS) out of the TXOP.
int PlannedAmpduBytes(State& s, int station, TimeNs rts_protection_ns);
// Airtime of an A-MPDU of `psdu_bytes` at `f`'s rate and of the BlockAck answering it (no SIFS).
TimeNs AmpduAndBlockAckNs(const QueuedFrame& f, int psdu_bytes);
// No BlockAck came after an A-MPDU or a BlockAckReq (ns-3's BlockAckTimeout, MissedBlockAck).
void BlockAckMissed(State& s, int station);
// An MPDU given up (retry limit, expiry, internal collision): ns-3's NotifyPacketDiscarded.
// An ADDBA Request: the agreement gets no reply. A Data frame sent under an agreement: a
// BlockAckReq moves the recipient's window past it.
void OnMpduDiscarded(State& s, int station, const QueuedFrame& f);
// A frame arrives at a full queue of `ac`: ns-3 3.37's WifiMacQueue::Insert wipes every expired
// MPDU, in-flight ones (an exchange under way) included; each of those owes a BlockAckReq
// (NotifyDiscardedMpdu), which goes after the exchange.
// Returns how many expired: the room they make in the queue.
size_t ExpireInFlight(State& s, int station, int ac);
// The ACK of an action frame came (ns-3's NotifyReceivedNormalAck): an ADDBA Request's starts
// the 1 ms wait for the Response.
void OnActionAcked(State& s, int station, const QueuedFrame& f);
// Receiver side: an A-MPDU, an ADDBA Request or Response, a BlockAckReq addressed here.
void ReceiveAmpdu(State& s, int station, const Transmission& tx, const RxEntry& entry);
void ReceiveAction(State& s, int station, const Transmission& tx, const RxEntry& entry);
void ReceiveBlockAckReqFrame(State& s, int station, const Transmission& tx, const RxEntry& entry);
// Originator side: the BlockAck awaited.
void ReceiveBlockAck(State& s, int station, const Transmission& tx);
// The BlockAck scheduled by ReceiveAmpdu or ReceiveBlockAckReqFrame goes on the air now.
void SendBlockAck(State& s, int station);
// After a successful exchange (its BlockAck or ACK came): with a TXOP limit of 0 and a
// BlockAckReq owed, the BlockAckReq is scheduled a SIFS later (true) and the frame in service
// moves on if `current_done`; false: nothing owed, the caller ends the exchange.
bool BlockAckReqFollows(State& s, int station, bool current_done);
// A SIFS after a BlockAck with a BlockAckReq owed (TXOP limit 0): the BlockAckReq, or a backoff.
void OnBlockAckReqDue(State& s, int station, int ac);

// ---- block_ack.cc
// Whether stations may set up Block Ack agreements: with aggregation, and on 802.11ac always
// (ns-3 3.37's NeedSetupBlockAck). QoS Data frames then count per receiver and TID and get
// their number when first sent.
bool UsesBlockAck(const State& s);
// ns-3 3.37's NeedSetupBlockAck: frame `f` of access category `ac` needs an ADDBA Request first.
bool NeedSetupBlockAck(State& s, int station, int ac, const QueuedFrame& f);
// The agreement of `station` as originator with `recipient` for `tid`, established, or null.
BaOriginator* EstablishedAgreement(State& s, int station, const MacAddress& recipient, int tid);
// The A-MPDU limit of `ac` for data at `mode` (0: no aggregation), ns-3's GetMaxAmpduSize.
uint32_t MaxAmpduBytes(const State& s, int ac, const PhyMode& mode);
// Receiver side: an MPDU of `source` under an agreement; delivers in order (reordering buffer).
void ReceiveUnderAgreement(State& s, int station, BaRecipient& agreement, uint16_t sequence_number,
                           const Bytes& ethernet, double power_dbm, double sinr);
BaRecipient* RecipientAgreement(State& s, int station, int source, int tid);
// The recipient's side of an ADDBA Request from `source`: a fresh buffer at the Request's
// starting sequence number (what an earlier agreement's buffer held is delivered first).
BaRecipient& CreateRecipientAgreement(State& s, int station, int source, int tid,
                                      uint16_t starting_sequence);
// Originator phases: Request sent (pending), its ACK (response timer), discarded at the retry
// limit (no reply), Response received (established).
void OnAddbaRequestSent(State& s, int station, const MacAddress& recipient, int tid);
void OnAddbaRequestAcked(State& s, int station, const MacAddress& recipient, int tid);
void OnAddbaRequestDiscarded(State& s, int station, const MacAddress& recipient, int tid);
void OnAddbaResponse(State& s, int station, const MacAddress& recipient, int tid);
// A compressed BlockAck of starting sequence number `ssn` and `bitmap` acknowledges the MPDU.
bool BlockAckCovers(uint16_t ssn, uint64_t bitmap, uint16_t sequence_number);
// BlockAckReq with starting sequence number `ssn`: flushes the buffer below it.
void ReceiveBlockAckReq(State& s, int station, BaRecipient& agreement, uint16_t ssn);
// ns-3's ReportAmpduTxStatus: the outcome of one A-MPDU (or BlockAckReq) exchange with
// `recipient` at the data rate `rate`: MPDUs acknowledged and not. The one place rate control
// learns from Block Acks (Minstrel-HT hooks here); Ideal takes the BlockAck's SNR.
void ReportAmpduTxStatus(State& s, int station, const MacAddress& recipient, int acked, int failed,
                         const RateEntry* rate, double block_ack_snr);

// ---- rate_control.cc
void BuildRates(State& s);
const RateEntry& RateFor(const State& s, const PhyMode& mode);
// The rate manager of `station` for config.rate_control (its rate set first).
std::unique_ptr<RateManager> MakeRateManager(const State& s, int station);
// Picks the DATA (and RTS) rate of the next attempt of the current frame of exchange_ac.
void ChooseRates(State& s, int station);

// ---- ideal_rate_manager.cc, minstrel_rate_manager.cc, minstrel_ht_rate_manager.cc
std::unique_ptr<RateManager> MakeIdealRateManager(const State& s);
// `seed` seeds its sample tables' stream. Minstrel for a/b/g, Minstrel-HT for n/ac.
std::unique_ptr<RateManager> MakeMinstrelRateManager(const State& s, uint64_t seed);
std::unique_ptr<RateManager> MakeMinstrelHtRateManager(const State& s, uint64_t seed);

// ---- transmission.cc
// `subframes`: an A-MPDU's MPDUs, moved into the transmission before any receiver sees it.
Transmission& StartTransmission(State& s, int source, FrameKind kind, const ModeEntry& mode,
                                int psdu_bytes, const MacAddress& ra, uint16_t duration_us,
                                std::vector<AmpduSubframe>* subframes = nullptr);
void OnTxEnd(State& s, int tx_id);
// With propagation_delay: signal entry `entry` of `tx_id` starts / ends at its receiver.
void OnSignalStart(State& s, int tx_id, int entry);
void OnSignalEnd(State& s, int tx_id, int entry);

// ---- reception.cc
void SignalArrives(State& s, int station, Transmission& tx, int entry_index);
// Removes the signal; returns true if it was the locked frame and decoded.
bool SignalEnds(State& s, int station, Transmission& tx, int entry_index);
void AbortReception(State& s, int station);  // Station starts transmitting.

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_MEDIUM_STATE_H_
