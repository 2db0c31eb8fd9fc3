// A-MPDU and Block Ack (block_ack.h, frame_exchange.cc): the A-MPDU length with delimiters and
// padding (IEEE 802.11-2016 9.7.1; ns-3 3.37's MpduAggregator), the agreement set up on the air
// as ns-3 does, the 5484 us PPDU limit, the Block Ack window, retransmission of lost MPDUs only,
// and the BlockAckReq after a missed BlockAck.
#include <gtest/gtest.h>

#include <vector>

#include "mac_phy_sim/block_ack.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::DrainTransmissions;
using testing::MakeEthernetFrame;

const MacAddress kA{{2, 0, 0, 0, 0, 1}}, kB{{2, 0, 0, 0, 0, 2}};

TEST(BlockAckTest, Debug) {
  MediumConfig config;
  config.standard = Standard::k80211n5GHz;
  config.mcs = 7;
  Medium medium(config);
  medium.EnableTrace(true);
  medium.AddStation(kA, {0, 0, 0});
  medium.AddStation(kB, {1, 0, 0});
  for (int i = 0; i < 100; ++i) medium.SubmitFrame(0, MakeEthernetFrame(kB, kA, 1500), 0);
  std::vector<Delivery> deliveries;
  medium.AdvanceTo(20 * kNsPerMs, &deliveries);
  for (const TxRecord& t : DrainTransmissions(medium)) {
    std::printf("%lld-%lld src %d kind %d seq %d ampdu %d rx %d\n", (long long)t.start_ns,
                (long long)t.end_ns, t.source, (int)t.kind, t.sequence_number,
                t.ampdu_reference ? (int)*t.ampdu_reference : -1,
                (int)t.receptions[0].outcome);
  }
  std::printf("deliveries %zu\n", deliveries.size());
}

}  // namespace
}  // namespace sitlnet::mac
