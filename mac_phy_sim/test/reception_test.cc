// PHY reception details that decide agreement with ns-3 3.37: the frame
// capture window (SimpleFrameCaptureModel) is measured from preamble
// detection whatever the PHY, not over the whole (192 us) DSSS preamble.
#include <gtest/gtest.h>

#include <vector>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

using testing::MakeEthernetFrame;

// 11b at 1 Mb/s, capture on (5 dB). B at 0, C at 45 m (weak at B), A at -10 m
// (20 dB stronger at B). C starts at DIFS (50 us); A at `a_start_us` (its
// frame arrives DIFS earlier). Returns the source of the first frame B
// receives, -1 if none.
int FirstSourceAtB(int a_start_us) {
  constexpr int kDifsUs = 50;
  MediumConfig config;
  config.standard = Standard::k80211b;
  config.rate_mbps = 1;
  config.reference_loss_db = 46.6777;  // Same geometry as the 11a capture test.
  config.capture_margin_db = 5;
  config.short_retry_limit = 1;
  Medium medium(config);
  const StationId b = medium.AddStation(RobotMac(0), {0, 0, 0});
  const StationId a = medium.AddStation(RobotMac(1), {-10, 0, 0});
  const StationId c = medium.AddStation(RobotMac(2), {45, 0, 0});
  medium.SubmitFrame(c, MakeEthernetFrame(RobotMac(0), RobotMac(2), 100), 0);
  medium.SubmitFrame(a, MakeEthernetFrame(RobotMac(0), RobotMac(1), 100),
                     (a_start_us - kDifsUs) * kNsPerUs);
  std::vector<Delivery> out;
  medium.AdvanceTo(5 * kNsPerMs, &out);
  for (const Delivery& d : out) {
    if (d.station == b) return d.source;
  }
  return -1;
}

TEST(ReceptionTest, CaptureWindowEndsSixteenMicrosecondsAfterPreambleDetection) {
  // ns-3: capture if the new frame arrives within CaptureWindow (16 us) of
  // the preamble detection, which ends 4 us into the frame: up to 20 us.
  EXPECT_EQ(FirstSourceAtB(50 + 10), 1);  // 10 us into C's frame: A captured.
  // 40 us into C's 192 us DSSS preamble: too late to switch; A's frame is
  // interference and C's is lost under it.
  EXPECT_EQ(FirstSourceAtB(50 + 40), -1);
}

}  // namespace
}  // namespace sitlnet::mac
