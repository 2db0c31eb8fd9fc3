// Medium counters as the daemon status and the run summary see them: the 802.11 medium's
// expired-frame count reaches MediumCounters and survives the proto round trip
// (medium.proto StationCounters, also the remote medium link's carrier).
#include <gtest/gtest.h>

#include "sitlnet/medium.pb.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

std::vector<uint8_t> EthernetFrame(const MacAddress& destination, const MacAddress& source,
                                   size_t payload_bytes) {
  std::vector<uint8_t> frame(14 + payload_bytes, 0x5a);
  std::copy(destination.bytes.begin(), destination.bytes.end(), frame.begin());
  std::copy(source.bytes.begin(), source.bytes.end(), frame.begin() + 6);
  frame[12] = 0x08;
  frame[13] = 0x00;
  return frame;
}

TEST(MediumCounters, ExpiredFramesReachTheCountersAndTheProto) {
  // Queue MaxDelay 1 ms. Robot b holds the air from t = 0 with a 2290-byte broadcast at the
  // 6 Mb/s group rate (> 3 ms); robot a's two frames, queued at 0.1 ms, are older than 1 ms at
  // a's next access and expire there (ns-3 3.37 FrameExchangeManager::StartTransmission).
  const Scenario scenario = LoadScenarioText(
      "name: \"counters\"\n"
      "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
      "robot { name: \"b\" position_m { x: 5 y: 0 z: 1 } }\n"
      "radio { queue_max_delay_ms: 1 }\n"
      "timing { pacing: PACING_LOCKSTEP seed: 3 }\n",
      "medium_counters_test");
  auto medium = MakeMacPhySimMedium(scenario);
  const MacAddress mac_a = scenario.robots[0].wlan_mac;
  const MacAddress mac_b = scenario.robots[1].wlan_mac;
  const MacAddress broadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
  medium->Submit(1, 0, EthernetFrame(broadcast, mac_b, 2290 - 14));
  medium->Submit(0, 100'000, EthernetFrame(mac_b, mac_a, 100));
  medium->Submit(0, 100'000, EthernetFrame(mac_b, mac_a, 100));
  std::vector<Delivery> deliveries;
  medium->AdvanceTo(50'000'000, &deliveries, nullptr);

  const MediumCounters counters = medium->Counters(0);
  EXPECT_EQ(counters.queue_expired, 2u);
  EXPECT_EQ(counters.queue_drops, 2u);  // Expired frames are queue drops too.

  proto::StationCounters wire;
  MediumCountersToProto(counters, &wire);
  EXPECT_EQ(wire.queue_expired(), 2u);
  const MediumCounters back = MediumCountersFromProto(wire);
  EXPECT_EQ(back.queue_expired, 2u);
  EXPECT_EQ(back.queue_drops, 2u);
}

}  // namespace
}  // namespace sitlnet::tapbridge
