// sitlnet mac_phy_sim: a deterministic discrete-event simulator of an 802.11
// DCF medium (MAC + PHY + channel with obstacle shadowing). Pure library: no
// sockets, no Linux calls, no global state. The model, its defaults, its
// sources and what it leaves out are described in docs/mac_phy_sim.md.
//
// Usage: build a MediumConfig, construct a Medium, AddStation() for every
// radio (ids are dense, 0, 1, 2, ... in the order added), AddObstacle() for
// every box, then alternate SubmitFrame() (Ethernet II frames, virtual time)
// and AdvanceTo(until_ns), which appends the deliveries due up to until_ns.
#ifndef SITLNET_MAC_PHY_SIM_MAC_PHY_SIM_H_
#define SITLNET_MAC_PHY_SIM_MAC_PHY_SIM_H_

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "common/common.h"

namespace sitlnet::mac {

//------------------------------- Configuration ------------------------------

enum class Standard : uint8_t {
  k80211a,  // OFDM, 5 GHz, 6..54 Mb/s (IEEE 802.11-2016 clause 17).
  k80211b,  // DSSS/CCK, 2.4 GHz, 1, 2, 5.5, 11 Mb/s (clauses 15, 16).
  k80211g,  // ERP, 2.4 GHz: ERP-OFDM 6..54 Mb/s and DSSS/CCK 1..11 Mb/s (clause 18), no protection.
  // HT (clause 19) on an 802.11g PHY: HT MCS for data, the 11g rates for control and group frames.
  k80211n2_4GHz,
  // HT on an 802.11a PHY (5 GHz).
  k80211n5GHz,
  // VHT (clause 21) on an 802.11a PHY (5 GHz).
  k80211ac,
};

// True for the HT and VHT standards (802.11n, 802.11ac): data goes at an MCS, stations are QoS
// stations (ns-3 3.37 allows nothing else).
bool IsHtOrVht(Standard standard);

// EDCA access categories, lowest priority first (IEEE 802.11-2016 10.22.2; docs/mac_phy_sim.md,
// "EDCA"). A higher value wins an internal collision.
enum class AccessCategory : uint8_t { kBackground, kBestEffort, kVideo, kVoice };
inline constexpr int kAccessCategoryCount = 4;

// The 802.11 user priority (0-7) of an Ethernet frame: its IPv4 DS byte >> 5 (IPv6: traffic
// class >> 5), as Linux before 6.8 and ns-3 3.37 classify; 0 for ARP and other non-IP frames.
int UserPriorityOf(std::span<const uint8_t> ethernet_frame);
// Table 10-1: user priority 1, 2 -> background; 0, 3 -> best effort; 4, 5 -> video; 6, 7 -> voice.
AccessCategory AccessCategoryOf(int user_priority);

// Contention parameters of one access category (or of the DCF).
struct EdcaParameters {
  int aifsn = 2;
  int cw_min = 15;
  int cw_max = 1023;
  TimeNs txop_limit_ns = 0;  // 0: one frame exchange per channel access.
  friend bool operator==(const EdcaParameters&, const EdcaParameters&) = default;
};
// ns-3 3.37's defaults (WifiMac::ConfigureDcf) from the PHY's aCWmin and aCWmax: AIFSN 7/3/2/2,
// CWmin aCWmin/aCWmin/(aCWmin+1)/2-1/(aCWmin+1)/4-1, CWmax aCWmax/aCWmax/aCWmin/(aCWmin+1)/2-1
// for BK/BE/VI/VO; TXOP limits VI 4.096 ms, VO 2.080 ms (DSSS PHYs: 6.016, 3.264), BE and BK 0.
EdcaParameters DefaultEdcaParameters(AccessCategory ac, int cw_min, int cw_max, bool dsss);

// Plain values only; every field has the default ns-3 3.37 uses (see
// docs/references.md#radio-defaults) unless noted. Validated by the Medium constructor. The
// library's own defaults, so it runs without a scenario; a scenario that leaves a radio field
// out yields the same config (scenario_adapter_test compares them), its ranges are the
// scenario's (proto/sitlnet/scenario.proto) and only asserted here.
struct MediumConfig {
  Standard standard = Standard::k80211a;
  double rate_mbps = 54;  // a/b/g: data rate of every station (no rate control); n/ac: unused.
  // 802.11n/ac only (a/b/g ignore these): the data mode of every station, as an ns-3 user writes
  // it. HT: mcs 0-15 is ns-3's HtMcs index (8 per stream: 0-7 one stream, 8-15 two). VHT: mcs 0-9
  // per stream, with spatial_streams (1-2). Widths: n 20/40 MHz, ac 20/40/80 MHz; VHT MCS 9 is
  // invalid at 20 MHz for 1 and 2 streams (ns-3's VhtPhy::IsCombinationAllowed).
  int mcs = 7;
  std::optional<int> spatial_streams;    // Unset: HT from the MCS (mcs / 8 + 1); VHT 1.
  std::optional<int> channel_width_mhz;  // Unset: ns-3 3.37's default, 20 (n) or 80 (ac).
  bool short_guard_interval = false;     // 400 ns GI (3.6 us symbols); ns-3's default is 800 ns.
  double tx_power_dbm = 16.0206;
  double noise_figure_db = 7;
  double rx_sensitivity_dbm = -101;    // Weaker signals are not even interference-tracked.
  double cca_energy_detect_dbm = -62;  // Energy at or above this makes CCA busy.
  double preamble_detect_snr_db = 4;   // ns-3 ThresholdPreambleDetectionModel.
  double preamble_detect_min_rssi_dbm = -82;
  // The path-loss model (path_loss_model.h; docs/mac_phy_sim.md, "Path-loss models").
  enum class PathLoss : uint8_t { kLogDistance, kTwoRayGround, kThreeGppV2vUrban, kThreeGppV2vHighway };
  PathLoss path_loss_model = PathLoss::kLogDistance;
  // Frequency of two-ray and 3GPP; unset: 5.15 GHz (11a) or 2.4 GHz (11b/g), the Friis reference.
  std::optional<double> path_loss_frequency_hz;
  double two_ray_height_above_z_m = 0;   // ns-3 TwoRayGround's HeightAboveZ.
  double two_ray_system_loss = 1;        // Linear, ns-3's SystemLoss.
  double two_ray_min_distance_m = 0.5;   // No loss at or below (ns-3's MinDistance).
  bool v2v_shadowing = true;             // 3GPP correlated shadow fading (ShadowingEnabled).
  double v2v_truck_percent = 0;          // Share of 3 m blockers (ns-3's PercType3Vehicles).
  TimeNs v2v_update_period_ns = 0;       // LOS/NLOSv redrawn after this; 0 never (UpdatePeriod).
  double path_loss_exponent = 3;            // Log-distance model.
  std::optional<double> reference_loss_db;  // Loss at 1 m; unset: Friis at the frequency.
  bool shadowing = true;                    // Sommer et al. 2011 obstacle model.
  double shadowing_db_per_wall = 9;         // beta
  double shadowing_db_per_m = 0.4;          // gamma
  // MPDUs (with aggregation: the whole A-MPDU, as in ns-3 3.37) longer than this use RTS/CTS;
  // 0: never.
  uint32_t rts_threshold_bytes = 0;
  // Per-station drop-tail transmit queue, the frame in service included
  // (ns-3 3.37 WifiMacQueue: MaxSize 500 packets, MaxDelay 500 ms; frames
  // older than the delay are dropped when a frame arrives at a full queue).
  uint32_t queue_limit_frames = 500;
  TimeNs queue_max_delay_ns = 500 * kNsPerMs;  // 0: frames never expire.
  // Rate of group-addressed (broadcast, multicast) DATA frames. Unset: the
  // lowest basic rate (6 Mb/s for 11a, 1 Mb/s DSSS for 11b/11g), as ns-3.
  std::optional<double> group_rate_mbps;
  // 11b/11g DSSS: short PPDU format (96 us instead of 192 us) at 5.5 and 11
  // Mb/s, as ns-3's WifiRemoteStationManager::SetShortPreambleEnabled.
  bool short_preamble = false;
  int short_retry_limit = 7;  // dot11ShortRetryLimit: attempts for short frames.
  int long_retry_limit = 4;   // dot11LongRetryLimit: attempts when RTS is used.
  std::optional<int> cw_min;  // Override of the standard's CWmin (tests).
  std::optional<int> cw_max;  // Override of the standard's CWmax (tests).
  // a/b/g: a QoS station with four EDCA access categories (ns-3's QosSupported) instead of the
  // DCF. n/ac stations are QoS stations whatever this says.
  bool qos = false;
  // 802.11n/ac only: A-MPDU aggregation under a Block Ack agreement (docs/mac_phy_sim.md,
  // "A-MPDU and Block Ack"). max_ampdu_bytes by AccessCategory (BK, BE, VI, VO) is ns-3
  // 3.37's {BK,BE,VI,VO}_MaxAmpduSize (WifiMac): 0 / 65535 / 65535 / 0; 0 turns an access
  // category's aggregation off. aggregation = false turns it off in all four (ns-3: every
  // *_MaxAmpduSize 0). a/b/g stations never aggregate. Off by default, unlike ns-3, until the
  // A-MPDU cells with several senders match it (docs/validation.md). 802.11ac stations set up
  // Block Ack agreements whatever these say, as ns-3 3.37 does (single MPDUs then).
  bool aggregation = false;
  std::array<uint32_t, kAccessCategoryCount> max_ampdu_bytes = {0, 65535, 65535, 0};
  bool short_slot = false;    // 802.11g only: 9 us slot instead of 20 us.
  // Frame capture (ns-3 SimpleFrameCaptureModel): while the preamble of the
  // frame being received is still in progress, switch to a new frame that is
  // this much stronger. Unset: no capture (ns-3's default).
  std::optional<double> capture_margin_db;
  // Channel effects ns-3 users reach for; all off by default (docs/mac_phy_sim.md).
  // Constant-speed propagation delay, distance / 299792458 m/s per receiver
  // (ns-3 ConstantSpeedPropagationDelayModel, the Yans default).
  bool propagation_delay = false;
  // Nakagami-m fast fading, one draw per frame and receiver (ns-3
  // NakagamiPropagationLossModel and its defaults): m0 below d1, m1 below d2,
  // m2 beyond. Rayleigh fading: every m = 1.
  bool nakagami_fading = false;
  double nakagami_m0 = 1.5, nakagami_m1 = 0.75, nakagami_m2 = 0.75;
  double nakagami_d1_m = 80, nakagami_d2_m = 200;
  // Log-normal shadowing: a fixed zero-mean Gaussian loss (dB) per station
  // pair, drawn from the seed; 0: off.
  double lognormal_shadowing_sigma_db = 0;
  // Jakes fading: time-correlated Rayleigh fading, one process per station pair, evaluated at
  // each frame's start (ns-3 JakesPropagationLossModel and JakesProcess, their defaults):
  // a fade lasts tens of ms at 80 Hz. Not together with nakagami_fading (docs/mac_phy_sim.md).
  bool jakes_fading = false;
  double jakes_doppler_hz = 80;  // Maximum Doppler frequency, (0, 1e4].
  int jakes_oscillators = 20;    // Oscillators per process, [4, 1000].
  // Not in ns-3: each pair's Doppler is sqrt(v_a^2 + v_b^2) / wavelength, the speeds taken
  // from the stations' moves (jakes_doppler.h); replaces jakes_doppler_hz.
  bool jakes_doppler_from_speed = false;
  // Data rate selection. kConstant: every station sends at its rate
  // (rate_mbps or its StationRadio). kIdeal: per destination, the highest
  // rate whose SNR for a bit error rate of ideal_ber is below the SNR the
  // destination last measured on an acknowledged frame (ns-3's
  // IdealWifiManager; starts at the lowest rate). kMinstrel: ns-3 3.37's
  // MinstrelWifiManager on a/b/g, MinstrelHtWifiManager on n/ac: per destination,
  // success statistics per rate, a sample table and a multi-rate retry chain
  // (docs/mac_phy_sim.md). kIdeal is a/b/g only.
  enum class RateControl : uint8_t { kConstant, kIdeal, kMinstrel };
  RateControl rate_control = RateControl::kConstant;
  double ideal_ber = 1e-6;  // ns-3 IdealWifiManager's BerThreshold.
  // ns-3 3.37 MinstrelWifiManager's attributes and defaults (UpdateStatistics, LookAroundRate,
  // EWMA, SampleColumn, PacketLength); MinstrelHtWifiManager's have the same names and
  // defaults, but UpdateStatistics is 50 ms there (ht_update_stats_ns; its legacy manager's
  // LegacyUpdateStatistics is update_stats_ns) and LookAroundRate is its legacy manager's.
  struct Minstrel {
    TimeNs update_stats_ns = 100 * kNsPerMs;  // Statistics refresh interval (a/b/g).
    TimeNs ht_update_stats_ns = 50 * kNsPerMs;  // The same for Minstrel-HT (n/ac).
    int look_around_percent = 10;             // Share of frames sent at a sampled rate.
    int ewma_percent = 75;                    // Weight of the old success probability.
    int sample_columns = 10;                  // Columns of the random sample table.
    int packet_bytes = 1200;                  // PSDU size of the rates' perfect TX times.
    friend bool operator==(const Minstrel&, const Minstrel&) = default;
  };
  Minstrel minstrel;
  // Error model of OFDM frames. kNist: ns-3's NistErrorRateModel (formulas;
  // what runs used before this field existed). kTableBased: ns-3 3.37's
  // TableBasedErrorRateModel, the default of its Wi-Fi PHY (PER tables from
  // link-level simulations). DSSS frames use ns-3's DSSS formulas with both.
  enum class ErrorModel : uint8_t { kNist, kTableBased };
  ErrorModel error_model = ErrorModel::kNist;
  uint64_t seed = 1;        // Every random draw derives from this (per-station streams).
  friend bool operator==(const MediumConfig&, const MediumConfig&) = default;
};

// Derived PHY/MAC constants of a config (what the medium actually uses).
struct PhyInfo {
  double frequency_mhz = 0;      // Channel centre: 5180 (11a, ch 36) or 2412 (b/g, ch 1).
  double noise_floor_dbm = 0;    // kTB over the data frames' bandwidth + noise figure.
  double reference_loss_db = 0;  // At 1 m.
  double path_loss_frequency_hz = 0;  // Of the two-ray and 3GPP models.
  double ack_rate_mbps = 0;      // Control-response rate for the configured data rate.
  double group_rate_mbps = 0;    // Rate of group-addressed DATA frames.
  TimeNs slot_ns = 0, sifs_ns = 0, difs_ns = 0, eifs_ns = 0;
  int cw_min = 0, cw_max = 0;
  // Contention. a/b/g without qos: the DCF, one queue (AIFSN 2: aifs_ns = difs_ns). QoS stations
  // (n/ac, or qos set): four EDCA queues with edca's parameters; aifsn, aifs_ns, eifs_ns and
  // cw_min/cw_max are then best effort's, where every frame without a DS marking goes.
  bool qos = false;
  int aifsn = 2;
  TimeNs aifs_ns = 0;  // aSIFSTime + aifsn x aSlotTime (10.22.2.4).
  // By AccessCategory; a DCF station uses only best effort's entry (its DCF parameters).
  std::array<EdcaParameters, kAccessCategoryCount> edca{};
};

// Computes the derived constants; throws Error("<field> <value> ...") for a rate the standard lacks
// or bad contention/retry settings, and aborts (SITLNET_DEMAND) on a value no formula can take:
// the scenario's field options bound the rest before a config is built.
PhyInfo DerivePhyInfo(const MediumConfig& config);

// The data rates of `standard` in Mb/s, from the one table of PHY modes (phy_mode.cc): DSSS/HR-DSSS
// 1, 2, 5.5, 11, then OFDM 6 .. 54; 802.11g has both (an ERP PHY has the DSSS rates, 18.1.1).
// The scenario's validation checks rates against it.
std::vector<double> RatesMbps(Standard standard);
// True if `rate_mbps` is one of RatesMbps(standard).
bool HasRate(Standard standard, double rate_mbps);

// Exact PPDU duration of a PSDU of `psdu_bytes` at `rate_mbps` (preamble,
// header, and for 802.11g the 6 us signal extension). Throws Error for a rate
// the standard does not have.
TimeNs PpduDurationNs(Standard standard, double rate_mbps, int psdu_bytes);

//------------------------------- Geometry -----------------------------------

// A box obstacle: centre, full edge lengths along its own axes, yaw about +z.
struct Box {
  Vec3d center_m;
  Vec3d size_m;
  double yaw_deg = 0;
};

using StationId = int;  // Dense: 0 .. station_count()-1, in the order added.

// Per-station radio settings; unset fields take the MediumConfig's.
struct StationRadio {
  std::optional<double> tx_power_dbm;  // Finite; the scenario bounds it (docs/scenario.md).
  std::optional<double> rate_mbps;     // A rate of the standard (kConstant rate control; a/b/g).
  std::optional<int> mcs;              // n/ac: an MCS valid with the config's streams and width.
};

//---------------------------- Outputs: deliveries ---------------------------

// A frame that reached a station's MAC intact (first copy; duplicates are
// filtered). Broadcast/multicast frames produce one Delivery per receiver.
struct Delivery {
  StationId station = 0;                // Receiver.
  StationId source = 0;                 // Transmitter of the frame.
  std::vector<uint8_t> ethernet_frame;  // As submitted (dst MAC, src MAC, type, payload).
  TimeNs delivery_ns = 0;               // End of the PPDU at the receiver.
  double rx_power_dbm = 0;
  double sinr_db = 0;  // Lowest SINR over the frame.
  friend bool operator==(const Delivery&, const Delivery&) = default;
};

//------------------------------ Outputs: trace ------------------------------

// kCfEnd: sent by a QoS station that ends its TXOP early (ns-3 3.37's SendCfEndIfNeeded); it
// resets the NAV of the stations that decode it.
// kBlockAck / kBlockAckReq: compressed BlockAck (32 B) and BlockAckReq (24 B), 9.3.1.8-9.
// kAction: an ADDBA Request or Response (Block Ack action frames, 9.6.5), 37 B.
enum class FrameKind : uint8_t { kData, kAck, kRts, kCts, kCfEnd, kBlockAck, kBlockAckReq, kAction };
inline constexpr FrameKind kLastFrameKind = FrameKind::kAction;

enum class RxOutcome : uint8_t {
  kReceived,          // Decoded (it may still be a duplicate or for another station).
  kCollided,          // Preamble missed or frame lost because of overlapping frames.
  kError,             // Decoding failed at the drawn error rate without interference.
  kBelowSensitivity,  // Too weak to detect (under sensitivity or preamble thresholds).
  kTransmitting,      // The receiver was itself transmitting (half duplex).
};

// Why a station did or did not decode a frame: the branch of the model that
// decided (reception.cc), finer than RxOutcome. Recorded with EnableCauses.
enum class RxCause : uint8_t {
  kUnknown,           // Causes were not recorded.
  kDecoded,           // Decoded (RxOutcome::kReceived).
  kBelowThreshold,    // Under the RX sensitivity, or under the preamble thresholds alone.
  kNoiseError,        // Locked, then lost at the error-rate draw with no interferer.
  kCollision,         // Lost to overlapping frames (preamble broken, taken over, SINR).
  kAlreadyReceiving,  // Arrived while locked on another frame; detectable alone.
  kOwnTransmission,   // The station was transmitting (at arrival, or started during it).
};

struct RxRecord {
  StationId station = 0;
  RxOutcome outcome = RxOutcome::kBelowSensitivity;
  double rx_power_dbm = 0;
  double sinr_db = 0;  // Lowest SINR over the frame; noise-only SNR when not locked.
  // With EnableCauses (else kUnknown, -1, 0, 0):
  RxCause cause = RxCause::kUnknown;
  // kCollision: the source of the strongest frame that overlapped it (at the
  // instant of the decision for a preamble, over the whole frame once
  // locked); kAlreadyReceiving: the source of the frame the station was
  // locked on. Else -1.
  StationId interferer = -1;
  // The loss at the frame's start split into log-distance path loss and
  // obstacle shadowing (rx power = tx power - both - log-normal + fading).
  // Under the sensitivity the obstacle part may be a lower bound (channel.h).
  double path_loss_db = 0;
  double obstacle_loss_db = 0;
  // DATA frames only: a box crosses the segment from the source to this station, whatever the
  // loss models made of it: a wall's loss at the frame's start, else the geometry at its end.
  bool obstructed = false;
};
// A wall's loss above this marks a path as obstructed without asking the geometry: above the
// rounding of (total - path - log-normal) loss, below any wall's loss.
inline constexpr double kObstructedMinLossDb = 0.01;

// One transmission on the air. Emitted when it ends, so the trace is ordered
// by end_ns (equal ends in event order); start_ns gives the pcap timestamp.
struct TxRecord {
  TimeNs start_ns = 0, end_ns = 0;
  StationId source = 0;
  FrameKind kind = FrameKind::kData;
  bool retry = false;            // Frame Control Retry bit.
  uint16_t sequence_number = 0;  // 12 bits; 0 for control frames.
  uint16_t duration_us = 0;      // Duration/ID field (NAV).
  double rate_mbps = 0;
  // HT/VHT DATA frames (else mcs = -1): what radiotap's MCS or VHT field carries.
  int mcs = -1;  // HT: 0-15 (streams included); VHT: 0-9 per stream.
  bool vht = false;
  int spatial_streams = 1;
  int channel_width_mhz = 20;
  bool short_guard_interval = false;
  bool qos = false;  // A QoS Data frame (QoS stations); its QoS Control field carries tid.
  // An MPDU of an A-MPDU: the A-MPDU's reference number (radiotap's A-MPDU status field; one
  // record per MPDU, all with the PPDU's start and end), and whether it is the last MPDU.
  std::optional<uint32_t> ampdu_reference;
  bool ampdu_last = false;
  // kAction: true for an ADDBA Response, false for a Request (its sequence_number is the
  // management frames' counter). The BlockAck's bitmap ba_bitmap.
  bool addba_response = false;
  uint16_t ba_starting_sequence = 0;  // ADDBA Request, BlockAckReq, BlockAck.
  uint64_t ba_bitmap = 0;
  uint8_t tid = 0;   // QoS Data: the frame's user priority (UserPriorityOf).
  MacAddress receiver;     // addr1 (broadcast for group frames).
  MacAddress transmitter;  // addr2 (absent on air for ACK/CTS; still filled).
  // DATA: the Ethernet frame carried, as submitted (shared with the queue, not copied); null
  // for control frames. MpduBytes() gives the bytes on air.
  std::shared_ptr<const std::vector<uint8_t>> ethernet_frame;
  std::vector<RxRecord> receptions;  // Every other station, by StationId.
};

// The exact MPDU of a transmission as sent (IEEE 802.11-2016 9.2.4, 9.3): for DATA an IBSS
// header (addr1 RA, addr2 TA, addr3 the stations' shared BSSID), RFC 1042 LLC/SNAP, the
// Ethernet type and payload; ACK/CTS/RTS as their control frames; each with its CRC-32 FCS.
// Built on demand (only a pcap needs the bytes): a function of the record's fields alone.
std::vector<uint8_t> MpduBytes(const TxRecord& tx);

enum class DropReason : uint8_t {
  kRetryLimit,
  kQueueFull,
  kQueueExpired,  // Waited longer than queue_max_delay_ns (removed when the queue was full).
};

struct DropRecord {
  TimeNs time_ns = 0;
  StationId station = 0;
  DropReason reason = DropReason::kQueueFull;
  MacAddress destination;
  // The frame's 802.11 sequence number if it was given one: a unicast frame gets it when it
  // goes into service, or with radio.aggregation when it is first sent (ns-3's QosTxop numbers
  // an MPDU at its first transmission). A frame dropped before has none: has_sequence_number
  // false, sequence_number 0.
  uint16_t sequence_number = 0;
  size_t ethernet_bytes = 0;
  bool has_sequence_number = false;
};

// Either a transmission or a drop; exactly one of the two is set.
struct TraceEvent {
  std::optional<TxRecord> tx;
  std::optional<DropRecord> drop;
};

//----------------------------- Counters -------------------------------------

struct StationCounters {
  // Transmit side.
  uint64_t frames_submitted = 0;  // Accepted by SubmitFrame.
  uint64_t malformed = 0;         // Rejected by SubmitFrame (too short/long).
  uint64_t queue_drops = 0;       // Dropped by the queue: arrived full, or expired in it.
  uint64_t queue_expired = 0;     // Of those, waited longer than queue_max_delay_ns.
  uint64_t data_tx = 0;           // DATA transmissions, retries included.
  uint64_t retries = 0;           // DATA transmissions with the Retry bit.
  uint64_t rts_tx = 0, cts_tx = 0, ack_tx = 0;
  uint64_t tx_failures = 0;       // ACK or CTS timeouts (collisions or errors).
  uint64_t sent_ok = 0;           // Unicast acknowledged, or group frame sent.
  uint64_t internal_collisions = 0;  // EDCA: access categories that lost to a higher one.
  uint64_t cf_end_tx = 0;            // EDCA: CF-End frames ending a TXOP early.
  uint64_t lost_retry_limit = 0;  // Dropped after the last attempt.
  // 802.11n/ac Block Ack (docs/mac_phy_sim.md, "A-MPDU and Block Ack").
  uint64_t ampdu_tx = 0;          // A-MPDUs sent (their MPDUs count in data_tx).
  uint64_t block_ack_tx = 0, block_ack_req_tx = 0, addba_tx = 0;
  // Receive side.
  uint64_t rx_delivered = 0;   // Deliveries to this station.
  uint64_t rx_duplicates = 0;  // Retransmissions already delivered.
  uint64_t rx_collided = 0, rx_error = 0, rx_below_sensitivity = 0;
};

//------------------------------- The medium ---------------------------------

// The simulated medium. Not thread-safe; movable, not copyable.
class Medium {
 public:
  explicit Medium(const MediumConfig& config);  // Throws Error on a bad config.
  ~Medium();
  Medium(Medium&&) noexcept;
  Medium& operator=(Medium&&) noexcept;

  const MediumConfig& config() const;
  const PhyInfo& phy() const;

  // Adds a radio; returns its id (= number of stations before the call).
  StationId AddStation(const MacAddress& mac, const Vec3d& position_m);
  // The same with its own tx power and/or data rate; throws Error naming the
  // field if one is out of range or not a rate of the standard.
  StationId AddStation(const MacAddress& mac, const Vec3d& position_m, const StationRadio& radio);
  int station_count() const;

  // Moves a station at virtual time max(at_ns, now_ns()). Frames already on
  // the air keep the power they started with.
  void SetStationPosition(StationId station, const Vec3d& position_m, TimeNs at_ns);

  // Adds an obstacle (any time; applies to transmissions starting later).
  void AddObstacle(const Box& box);

  // Queues `ethernet_frame` (>= 14 bytes: dst MAC, src MAC, ethertype,
  // payload; at most 2304 bytes of MSDU) at station `source` at virtual time
  // max(at_ns, now_ns()). A group destination MAC means no ACK and no retry.
  // The bytes are copied. Returns false (and counts `malformed`) if rejected.
  bool SubmitFrame(StationId source, std::span<const uint8_t> ethernet_frame, TimeNs at_ns);

  // Runs every event with time <= until_ns, appends deliveries in time order
  // to *deliveries (may be null), and sets now_ns() to until_ns.
  void AdvanceTo(TimeNs until_ns, std::vector<Delivery>* deliveries);

  // Time of the earliest pending event, nullopt if none (a realtime driver
  // sleeps until then or until a new frame arrives).
  std::optional<TimeNs> NextEventNs();
  TimeNs now_ns() const;

  // Tracing is off by default and costs nothing then. Enabled, every
  // transmission and drop is buffered until DrainTrace moves it out.
  void EnableTrace(bool enabled);
  void DrainTrace(std::vector<TraceEvent>* out);
  // Off by default. On (with the trace), every RxRecord carries its cause,
  // interferer and loss split; nothing else changes (same draws, same
  // outcomes). Turn on before the first frame: a signal already on the air
  // when it is turned on is not known as an interferer.
  void EnableCauses(bool enabled);

  const StationCounters& counters(StationId station) const;
  size_t queued_frames(StationId station) const;  // Waiting, excluding the one in service.

  // Channel loss between two stations at their current positions (dB,
  // path loss + shadowing), from the cache. For links too weak to reach the
  // RX sensitivity, shadowing is summed only until that is certain, so the
  // value is then a lower bound >= tx_power_dbm - rx_sensitivity_dbm.
  double LossDb(StationId a, StationId b);

  struct State;  // Opaque: defined in medium_state.h, internal to the library.

 private:
  std::unique_ptr<State> state_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_MAC_PHY_SIM_H_
