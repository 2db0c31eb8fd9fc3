// Saturated-traffic driver shared by the validation tests and the benchmark:
// every sender's source offers frames faster than the medium carries them,
// exactly as the ns-3 side of the side-by-side does (side_by_side_case.h), so
// its queue never runs empty, as in Bianchi's model (1500-byte payloads, i.e.
// 1514-byte Ethernet frames, 1536-byte MPDUs).
#ifndef SITLNET_MAC_PHY_SIM_TEST_SATURATION_HARNESS_H_
#define SITLNET_MAC_PHY_SIM_TEST_SATURATION_HARNESS_H_

#include <cstdint>
#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/side_by_side_case.h"

namespace sitlnet::mac::testing {

enum class Topology { kRing, kSink };

struct SaturationSetup {
  int stations = 5;       // Contending senders (n of Bianchi's model).
  double rate_mbps = 54;  // 802.11a.
  Topology topology = Topology::kRing;
  TimeNs warmup_ns = 1 * kNsPerS;
  TimeNs measure_ns = 5 * kNsPerS;
  int payload_bytes = 1500;
  uint64_t seed = 1;
  // Bianchi's assumption: retries never give up (CW stays at CWmax).
  int retry_limit = 1000000;
};

struct SaturationResult {
  double throughput_mbps = 0;        // Payload bits delivered per second of measurement.
  uint64_t frames_delivered = 0;     // In the measurement window.
  double collision_probability = 0;  // Failed DATA attempts / DATA attempts (all time).
};

// Ethernet II frame from station `from` to `to` with `payload_bytes` of payload.
std::vector<uint8_t> MakeEthernetFrame(const MacAddress& to, const MacAddress& from,
                                       int payload_bytes);

SaturationResult RunSaturation(const SaturationSetup& setup);

// Moves the transmissions of the medium's trace out (drops are left out).
std::vector<TxRecord> DrainTransmissions(Medium& medium);

// The DATA frames of one link `distance_m` long under `config`: station 0 sends station 1 a
// 1500-byte payload every `interval_ns` for `duration_ns` (rate-control tests).
std::vector<TxRecord> LinkDataFrames(const MediumConfig& config, double distance_m,
                                     TimeNs interval_ns, TimeNs duration_ns);

// The medium's own cost: n saturated 802.11a 54 Mb/s stations 1 mm apart in
// a ring (n = 1: to a receive-only station), 1500-byte payloads, retries
// unlimited, with a light driver that keeps 16 frames queued per sender
// (topped up every 2 ms) for `seconds` of virtual time. Returns the number
// of transmissions (DATA, ACK). Used by the benchmarks' timing, not for
// validation (RunCase offers traffic exactly as the ns-3 side does).
uint64_t RunTopUpSaturation(int n, double seconds, uint64_t seed);

// The medium configuration of a side-by-side cell (the ns-3 half configures
// ns-3 from the same values: reference loss, control rate).
MediumConfig ConfigForCase(const side_by_side::Case& c, uint64_t seed);
// Loss (dB) between every pair of the cell's stations, row-major, as the
// medium computes it for `seed` (log-normal shadowing included).
std::vector<double> LinkLossesDb(const side_by_side::Case& c, uint64_t seed);
// Runs a side-by-side cell: every flow of its layout saturated.
SaturationResult RunCase(const side_by_side::Case& c, uint64_t seed);

}  // namespace sitlnet::mac::testing

#endif  // SITLNET_MAC_PHY_SIM_TEST_SATURATION_HARNESS_H_
