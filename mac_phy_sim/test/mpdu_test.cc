#include "mac_phy_sim/mpdu.h"

#include <gtest/gtest.h>

#include <string_view>

#include "mac_phy_sim/phy_mode.h"
#include "mac_phy_sim/test/saturation_harness.h"

namespace sitlnet::mac {
namespace {

TEST(MpduTest, Crc32CheckValue) {
  // The CRC-32 catalogue check value: "123456789" -> 0xCBF43926.
  const std::string_view text = "123456789";
  EXPECT_EQ(Crc32({reinterpret_cast<const uint8_t*>(text.data()), text.size()}), 0xCBF43926u);
}

TEST(MpduTest, DataFrameLayout) {
  const auto ethernet = testing::MakeEthernetFrame(RobotMac(2), RobotMac(1), 100);
  std::vector<uint8_t> mpdu;
  BuildDataMpdu(RobotMac(2), RobotMac(1), 44, 0x123, true, ethernet, &mpdu);
  ASSERT_EQ(static_cast<int>(mpdu.size()), MpduBytesForEthernet(ethernet.size()));
  EXPECT_EQ(mpdu[0], 0x08);
  EXPECT_EQ(mpdu[1], 0x08);  // Retry.
  EXPECT_EQ(mpdu[2], 44);
  EXPECT_EQ(mpdu[4 + 5], RobotMac(2).bytes[5]);   // addr1
  EXPECT_EQ(mpdu[10 + 5], RobotMac(1).bytes[5]);  // addr2
  EXPECT_EQ(mpdu[22] | (mpdu[23] << 8), 0x123 << 4);
  EXPECT_EQ(mpdu[24], 0xAA);
  EXPECT_EQ(mpdu[30], 0x08);  // Ethertype after LLC/SNAP.
  // The FCS makes the CRC residue of the whole frame constant (0x2144DF1C).
  EXPECT_EQ(Crc32(mpdu), 0x2144DF1Cu);
}

TEST(MpduTest, ControlFrameSizes) {
  std::vector<uint8_t> out;
  BuildControlMpdu(FrameKind::kAck, RobotMac(1), RobotMac(2), 0, &out);
  EXPECT_EQ(out.size(), static_cast<size_t>(kAckBytes));
  EXPECT_EQ(out[0], 0xD4);
  BuildControlMpdu(FrameKind::kCts, RobotMac(1), RobotMac(2), 0, &out);
  EXPECT_EQ(out.size(), static_cast<size_t>(kCtsBytes));
  BuildControlMpdu(FrameKind::kRts, RobotMac(1), RobotMac(2), 300, &out);
  EXPECT_EQ(out.size(), static_cast<size_t>(kRtsBytes));
  EXPECT_EQ(out[0], 0xB4);
}

}  // namespace
}  // namespace sitlnet::mac
