// One cell of the ns-3 side-by-side matrix (bench/ns3_reference/) and its
// geometry: which stations exist, where, and which of them send saturated
// traffic to whom. Plain C++17 and the standard library only, because the
// ns-3 half of the benchmark is compiled as C++17 and includes it too.
#ifndef SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CASE_H_
#define SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CASE_H_

#include <cstdint>
#include <string>
#include <vector>

namespace sitlnet::side_by_side {

// kN24, kN5: 802.11n at 2.4 / 5 GHz; kAc: 802.11ac (5 GHz). Their cells send at `mcs`.
enum class Standard { kA, kB, kG, kN24, kN5, kAc };
enum class Topology {
  kRing,     // `senders` stations 1 mm apart, i sends to i + 1 (ns-3's Bianchi validation).
  kSink,     // `senders` stations 1 mm apart send to one more, receive-only station.
  kHidden,   // A -> B <- C on a line: A-B `near_m`, B-C `far_m`; A and C out of each other's range.
  kExposed,  // B <- A   C -> D: A-C `far_m` (they hear each other), A-B = C-D = `near_m`.
  kLink,     // One sender, one receiver `near_m` away (for fading and shadowing cells).
};

// The path-loss model on both sides (mac_phy_sim's radio.path_loss_model, ns-3's loss model).
enum class PathLoss {
  kLogDistance,   // Exponent 3 from the 1 m loss of the standard's frequency.
  kTwoRayGround,  // ns-3's TwoRayGroundPropagationLossModel at 5.15 GHz.
  kV2vUrban,      // ns-3's ThreeGppV2vUrbanPropagationLossModel + its condition model, 5.15 GHz.
  kV2vHighway,    // The same, highway.
  // The same without shadow fading: with both antennas above the cars (NLOSv adds 0 dB) the
  // loss is the LOS formula whatever the condition, so delivery is deterministic.
  kV2vUrbanNoShadowing,
  kV2vHighwayNoShadowing,
};
inline bool IsV2v(PathLoss p) {
  return p != PathLoss::kLogDistance && p != PathLoss::kTwoRayGround;
}
inline bool IsV2vUrban(PathLoss p) {
  return p == PathLoss::kV2vUrban || p == PathLoss::kV2vUrbanNoShadowing;
}
inline bool HasV2vShadowing(PathLoss p) {
  return p == PathLoss::kV2vUrban || p == PathLoss::kV2vHighway;
}
// Antenna height of the link stations: two-ray at TR 37.885's vehicle antenna (1.5 m; two-ray
// loses everything at height 0); 3GPP at 2 m, above TR 37.885's 1.6 m cars, so NLOSv adds no
// blockage loss (a drone flies above the traffic).
inline double AntennaHeightM(PathLoss p) { return IsV2v(p) ? 2.0 : 1.5; }

// ConstantRateWifiManager, IdealWifiManager, MinstrelWifiManager.
enum class RateControl { kConstant = 0, kIdeal = 1, kMinstrel = 2 };

struct Case {
  std::string id;  // Unique, stable: names the CSV row.
  Standard standard = Standard::kA;
  bool short_slot = false;  // 11g only.
  double rate_mbps = 54;  // n/ac: the MCS's data rate (sizes the offered load; not configured).
  // n/ac only: ns-3's HtMcs / VhtMcs index (one spatial stream), width and guard interval.
  int mcs = -1;
  int channel_width_mhz = 20;
  bool short_gi = false;
  // n/ac only: A-MPDU and Block Ack with ns-3 3.37's defaults on both sides (BE 65535 B); else
  // off on both (ns-3: BE_MaxAmpduSize 0). In the CSV as the id's "-ampdu" suffix (IsAmpduId).
  bool ampdu = false;
  int senders = 5;
  Topology topology = Topology::kRing;
  int payload_bytes = 1500;          // Ethernet/packet payload; MPDU = payload + 36 bytes.
  uint32_t rts_threshold_bytes = 0;  // 0: no RTS/CTS.
  bool capture = false;              // SimpleFrameCaptureModel, 5 dB margin.
  double nakagami_m = 0;             // Nakagami fading with this m at every distance; 0: off.
  double lognormal_sigma_db = 0;     // Log-normal shadowing per link; 0: off.
  // Rate control; rate_mbps then only sizes the offered load. In the CSV as 0, 1, 2.
  RateControl rate_control = RateControl::kConstant;
  // Error model: ns-3's TableBasedErrorRateModel (the default of its PHY) on
  // both sides instead of NistErrorRateModel.
  bool table_error_model = false;
  double near_m = 0, far_m = 0;  // Hidden/exposed geometry.
  PathLoss path_loss = PathLoss::kLogDistance;
  // 3GPP only: ns-3's UpdatePeriod of the condition model (radio.v2v_update_period_ms); 0:
  // frozen. In the CSV's path_loss column as a suffix "-update<N>ms" (CellPathLossName).
  int v2v_update_period_ms = 0;
  double warmup_s = 1, measure_s = 10;
  // Bianchi's assumption for saturation (CW stays at CWmax); otherwise the
  // standard's 7 / 4 attempts.
  bool unlimited_retries = true;
  bool fast = false;  // Part of the subset scripts/test checks against the CSV.
  // Seeds each side for this cell; 0: the matrix run's count. Cells whose statistic varies
  // mostly between seeds (3GPP shadowing: one draw per static link per run) need thousands.
  // In the CSV as the row's `seeds`.
  int seeds = 0;
  // Source interval override (ns); 0: OfferIntervalNs's default. Not in the
  // CSV: for one-off load studies (ns3_side_by_side hidden-load).
  int64_t offer_interval_ns = 0;
  // Jakes fading with ns-3's defaults (80 Hz, 20 oscillators). Not in the CSV: only
  // ns3_jakes_side_by_side runs such cells.
  bool jakes = false;
  // EDCA cells (kSink only): every sender saturates two access categories, user priority
  // `high_priority` (6: voice, 5: video) and 0 (best effort), and the cell measures the
  // throughput of `measured_priority`'s frames. -1: one flow per sender at priority 0.
  int high_priority = -1;
  int measured_priority = 0;
  bool qos = false;  // a/b/g: QoS stations (ns-3's QosSupported); n/ac always are.
};
inline bool IsEdcaCell(const Case& c) { return c.high_priority >= 0; }
inline bool IsAmpduId(const std::string& id) {
  return id.size() > 6 && id.compare(id.size() - 6, 6, "-ampdu") == 0;
}

struct Point {
  double x = 0, y = 0, z = 0;
};
struct Flow {
  int from = 0, to = 0;
  int priority = 0;  // 802.11 user priority (IPv4 DS byte >> 5; ns-3's socket priority).
};
struct Layout {
  std::vector<Point> positions;
  std::vector<Flow> flows;
};

inline Layout MakeLayout(const Case& c) {
  Layout layout;
  switch (c.topology) {
    case Topology::kRing:
      for (int i = 0; i < c.senders; ++i) {
        layout.positions.push_back({0.001 * i, 0, 0});
        layout.flows.push_back({i, (i + 1) % c.senders});
      }
      break;
    case Topology::kSink:
      for (int i = 0; i <= c.senders; ++i) layout.positions.push_back({0.001 * i, 0, 0});
      for (int i = 1; i <= c.senders; ++i) {
        if (IsEdcaCell(c)) layout.flows.push_back({i, 0, c.high_priority});
        layout.flows.push_back({i, 0, 0});
      }
      break;
    case Topology::kHidden:
      layout.positions = {{0, 0, 0}, {c.near_m, 0, 0}, {c.near_m + c.far_m, 0, 0}};
      layout.flows = {{0, 1}, {2, 1}};
      break;
    case Topology::kExposed:
      layout.positions = {
          {0, 0, 0}, {-c.near_m, 0, 0}, {c.far_m, 0, 0}, {c.far_m + c.near_m, 0, 0}};
      layout.flows = {{0, 1}, {2, 3}};
      break;
    case Topology::kLink:
      if (c.path_loss != PathLoss::kLogDistance) {
        const double z = AntennaHeightM(c.path_loss);
        layout.positions = {{0, 0, z}, {c.near_m, 0, z}};
        layout.flows = {{0, 1}};
        break;
      }
      layout.positions = {{0, 0, 0}, {c.near_m, 0, 0}};
      layout.flows = {{0, 1}};
      break;
  }
  return layout;
}

// The traffic both simulators offer: every flow's source queues one packet
// per interval, starting 1 ms after the previous flow's (ns-3's
// PacketSocketClient as the side-by-side configures it). The interval is half
// the time one station alone needs per frame (DIFS + mean backoff + DATA +
// SIFS + ACK, roughly), so every queue stays full: the medium, not the
// source, sets the throughput. Queues then hold 500 frames and frames expire
// after 500 ms (ns-3's WifiMacQueue defaults), as in ns-3.
inline int64_t OfferIntervalNs(const Case& c) {
  if (c.offer_interval_ns > 0) return c.offer_interval_ns;
  const bool dsss = c.rate_mbps == 1 || c.rate_mbps == 2 || c.rate_mbps == 5.5 || c.rate_mbps == 11;
  const bool five_ghz = c.standard == Standard::kA || c.standard == Standard::kN5 ||
                        c.standard == Standard::kAc;
  const double slot_us = five_ghz || c.short_slot ? 9 : 20;
  const double bits = 8.0 * (c.payload_bytes + 36);
  const double data_us = (dsss ? 192 : 20) + bits / c.rate_mbps;
  const double cycle_us = 50 + 7.5 * slot_us + data_us + 250;
  // A-MPDUs carry frames faster than one per cycle (up to 64 per access): eight times the load.
  return static_cast<int64_t>(cycle_us * 1000 / (c.ampdu ? 8 : 2));
}
inline int64_t OfferStartNs(int flow_index) { return 1000000LL * flow_index; }

inline const char* PathLossName(PathLoss p) {
  switch (p) {
    case PathLoss::kLogDistance:
      return "log";
    case PathLoss::kTwoRayGround:
      return "tworay";
    case PathLoss::kV2vUrban:
      return "v2v-urban";
    case PathLoss::kV2vHighway:
      return "v2v-highway";
    case PathLoss::kV2vUrbanNoShadowing:
      return "v2v-urban-noshadowing";
    case PathLoss::kV2vHighwayNoShadowing:
      return "v2v-highway-noshadowing";
  }
  return "";
}

// The CSV's path_loss column of a cell: the model's name, then "-update<N>ms" if set.
inline std::string CellPathLossName(const Case& c) {
  std::string name = PathLossName(c.path_loss);
  if (c.v2v_update_period_ms > 0) {
    name += "-update" + std::to_string(c.v2v_update_period_ms) + "ms";
  }
  return name;
}

inline const char* StandardName(Standard s) {
  switch (s) {
    case Standard::kA:
      return "a";
    case Standard::kB:
      return "b";
    case Standard::kG:
      return "g";
    case Standard::kN24:
      return "n24";
    case Standard::kN5:
      return "n5";
    case Standard::kAc:
      return "ac";
  }
  return "?";
}
inline bool IsHtOrVht(Standard s) {
  return s == Standard::kN24 || s == Standard::kN5 || s == Standard::kAc;
}
inline const char* TopologyName(Topology t) {
  switch (t) {
    case Topology::kRing:
      return "ring";
    case Topology::kSink:
      return "sink";
    case Topology::kHidden:
      return "hidden";
    case Topology::kExposed:
      return "exposed";
    case Topology::kLink:
      return "link";
  }
  return "?";
}

}  // namespace sitlnet::side_by_side

#endif  // SITLNET_MAC_PHY_SIM_TEST_SIDE_BY_SIDE_CASE_H_
