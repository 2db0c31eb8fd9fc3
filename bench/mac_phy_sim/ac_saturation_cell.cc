#include "bench/mac_phy_sim/ac_saturation_cell.h"

#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac::bench {

side_by_side::Case AcSaturationCell(int senders, double measure_s, bool ampdu) {
  side_by_side::Case c;
  c.standard = side_by_side::Standard::kAc;
  c.mcs = 9;
  c.channel_width_mhz = 80;
  c.rate_mbps = McsModeFor(Standard::k80211ac, 9, 1, 80, false).rate_mbps;  // Sizes the load.
  c.ampdu = ampdu;
  c.senders = senders;
  c.topology = side_by_side::Topology::kSink;
  c.warmup_s = 0.5;
  c.measure_s = measure_s;
  // One sender alone: OfferIntervalNs's load (one frame per 52 us, 230 Mb/s) is under what
  // 64-MPDU A-MPDUs carry (about 350 Mb/s), so ns-3's packet socket offers 460 Mb/s (1.3 times).
  if (senders == 1) c.offer_interval_ns = 26000;
  return c;
}

TopUpOutcome RunAcSaturationCell(const side_by_side::Case& c, uint64_t seed) {
  MediumConfig config = testing::ConfigForCase(c, seed);
  config.max_ampdu_bytes[static_cast<int>(AccessCategory::kBestEffort)] = kVhtMaxAmpduBytes;
  TopUpSetup setup;
  setup.layout = side_by_side::MakeLayout(c);
  setup.payload_bytes = c.payload_bytes;
  setup.warmup_ns = static_cast<TimeNs>(c.warmup_s * 1e9);
  setup.measure_ns = static_cast<TimeNs>(c.measure_s * 1e9);
  return RunTopUp(config, setup);
}

}  // namespace sitlnet::mac::bench
