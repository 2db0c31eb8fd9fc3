// Radiotap/802.11 encoding against the radiotap field definitions and the
// 802.11 frame formats; the decoded view is checked by tshark in
// tests/integration/tapbridge_pcap_test.cc.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <memory>

#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

uint32_t Le32(const std::string& s, size_t at) {
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= uint32_t{static_cast<uint8_t>(s[at + i])} << (8 * i);
  return v;
}

const std::vector<uint8_t> kEthernet = {0x02, 0, 0, 0, 0,    1,    0x02, 0,
                                        0,    0, 0, 0, 0x08, 0x00, 0x45, 0x00};

AirFrame DataFrame() {
  AirFrame f;
  f.tx.start_ns = 1'234'567'891;
  f.tx.rate_mbps = 54;
  f.tx.sequence_number = 5;
  f.tx.retry = true;
  std::copy_n(kEthernet.begin(), 6, f.tx.receiver.bytes.begin());
  std::copy_n(kEthernet.begin() + 6, 6, f.tx.transmitter.bytes.begin());
  f.tx.ethernet_frame = std::make_shared<const std::vector<uint8_t>>(kEthernet);
  f.signal_dbm = -47.4;
  f.noise_dbm = -93.97;
  return f;
}

TEST(PcapWriter, FileHeaderIsNanosecondRadiotap) {
  const std::string header = PcapFileHeader();
  ASSERT_EQ(header.size(), 24u);
  EXPECT_EQ(Le32(header, 0), 0xa1b23c4du);
  EXPECT_EQ(Le32(header, 20), 127u);  // DLT_IEEE802_11_RADIO
}

TEST(PcapWriter, RadiotapFieldsAtTheirAlignedOffsets) {
  const std::string record = EncodePcapRecord(DataFrame(), 0);
  const std::string rt = record.substr(16);
  EXPECT_EQ(Le32(record, 0), 1u);            // seconds
  EXPECT_EQ(Le32(record, 4), 234'567'891u);  // nanoseconds
  ASSERT_GE(rt.size(), 25u);
  EXPECT_EQ(static_cast<uint8_t>(rt[2]), 25);     // it_len
  EXPECT_EQ(Le32(rt, 4), 0x86fu);                 // TSFT Flags Rate Channel Signal Noise Antenna
  EXPECT_EQ(Le32(rt, 8), 1'234'567u);             // TSFT, microseconds
  EXPECT_EQ(static_cast<uint8_t>(rt[16]), 0x10);  // FCS at end, FCS good
  EXPECT_EQ(static_cast<uint8_t>(rt[17]), 108);   // 54 Mb/s in 500 kb/s units
  EXPECT_EQ(static_cast<uint8_t>(rt[18]) | static_cast<uint8_t>(rt[19]) << 8, 5180);
  EXPECT_EQ(static_cast<uint8_t>(rt[20]) | static_cast<uint8_t>(rt[21]) << 8, 0x0140);
  EXPECT_EQ(static_cast<int8_t>(rt[22]), -47);
  EXPECT_EQ(static_cast<int8_t>(rt[23]), -94);
}

TEST(PcapWriter, DataFrameHeaderSnapAndFcs) {
  const std::vector<uint8_t> mpdu = Encode80211Mpdu(DataFrame());
  // 24-byte header + 8 LLC/SNAP + 2 payload bytes + 4 FCS: Ethernet + 22
  // (docs/references.md#80211-timing).
  ASSERT_EQ(mpdu.size(), kEthernet.size() + 22);
  EXPECT_EQ(mpdu[0], 0x08);
  EXPECT_EQ(mpdu[1], 0x08);    // Retry
  EXPECT_EQ(mpdu[4 + 5], 1);   // addr1 = DA
  EXPECT_EQ(mpdu[10 + 5], 0);  // addr2 = SA
  EXPECT_EQ(mpdu[22] | mpdu[23] << 8, 5 << 4);
  const uint8_t snap[8] = {0xaa, 0xaa, 0x03, 0, 0, 0, 0x08, 0x00};
  EXPECT_TRUE(std::equal(snap, snap + 8, mpdu.begin() + 24));
  const uint32_t crc = crc32(0, mpdu.data(), mpdu.size() - 4);
  const size_t n = mpdu.size();
  EXPECT_EQ(mpdu[n - 4] | mpdu[n - 3] << 8 | mpdu[n - 2] << 16 | uint32_t{mpdu[n - 1]} << 24, crc);
}

TEST(PcapWriter, FailedFrameHasBadFcsFlagAndBadFcs) {
  AirFrame f = DataFrame();
  f.failed = true;
  const std::string record = EncodePcapRecord(f, 0);
  EXPECT_EQ(static_cast<uint8_t>(record[16 + 16]), 0x50);
  const std::vector<uint8_t> mpdu = Encode80211Mpdu(f);
  const uint32_t crc = crc32(0, mpdu.data(), mpdu.size() - 4);
  const size_t n = mpdu.size();
  EXPECT_NE(mpdu[n - 4] | mpdu[n - 3] << 8 | mpdu[n - 2] << 16 | uint32_t{mpdu[n - 1]} << 24, crc);
}

TEST(PcapWriter, ControlFrameSizes) {
  AirFrame f;
  f.tx.kind = mac::FrameKind::kAck;
  EXPECT_EQ(Encode80211Mpdu(f).size(), 14u);  // ACK 14 B (docs/references.md#80211-timing)
  f.tx.kind = mac::FrameKind::kCts;
  EXPECT_EQ(Encode80211Mpdu(f).size(), 14u);
  f.tx.kind = mac::FrameKind::kRts;
  EXPECT_EQ(Encode80211Mpdu(f).size(), 20u);  // RTS 20 B
}

}  // namespace
}  // namespace sitlnet::tapbridge
