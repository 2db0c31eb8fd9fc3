// Radiotap/802.11 encoding against the radiotap field definitions and the
// 802.11 frame formats; tshark decodes the HT/VHT fields here (TsharkDecodesMcsBandwidthAndGi).
#include <gtest/gtest.h>
#include <zlib.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>

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

// An 802.11n QoS data frame at HT MCS 7, 40 MHz, short GI; an 802.11ac one at VHT MCS 9 x 2
// streams, 80 MHz, at voice (TID 6: `ping -Q 0xc0`).
AirFrame HtFrame(bool vht) {
  AirFrame f = DataFrame();
  f.tx.qos = true;
  f.tx.tid = vht ? 6 : 0;
  f.tx.vht = vht;
  f.tx.mcs = vht ? 9 : 7;
  f.tx.spatial_streams = vht ? 2 : 1;
  f.tx.channel_width_mhz = vht ? 80 : 40;
  f.tx.short_guard_interval = !vht;
  f.tx.rate_mbps = vht ? 780 : 150;
  return f;
}

TEST(PcapWriter, HtFramesCarryTheMcsField) {
  const std::string rt = EncodePcapRecord(HtFrame(false), 0).substr(16);
  EXPECT_EQ(static_cast<uint8_t>(rt[2]), 28);                 // it_len
  EXPECT_EQ(Le32(rt, 4), 0x86bu | 1u << 19);                  // no Rate; MCS
  EXPECT_EQ(static_cast<uint8_t>(rt[17]), 0);                 // pad where Rate was
  EXPECT_EQ(static_cast<uint8_t>(rt[18]) | static_cast<uint8_t>(rt[19]) << 8, 5180);
  EXPECT_EQ(static_cast<uint8_t>(rt[25]), 0x17);              // bandwidth, MCS, GI, FEC known
  EXPECT_EQ(static_cast<uint8_t>(rt[26]), 0x05);              // 40 MHz, short GI
  EXPECT_EQ(static_cast<uint8_t>(rt[27]), 7);                 // MCS index
  EXPECT_EQ(static_cast<uint8_t>(rt[28]), 0x88);              // QoS Data after the header
}

TEST(PcapWriter, VhtFramesCarryTheVhtField) {
  const std::string rt = EncodePcapRecord(HtFrame(true), 0).substr(16);
  EXPECT_EQ(static_cast<uint8_t>(rt[2]), 38);
  EXPECT_EQ(Le32(rt, 4), 0x86bu | 1u << 21);
  EXPECT_EQ(static_cast<uint8_t>(rt[26]) | static_cast<uint8_t>(rt[27]) << 8, 0x44);  // known
  EXPECT_EQ(static_cast<uint8_t>(rt[28]), 0);     // long GI
  EXPECT_EQ(static_cast<uint8_t>(rt[29]), 4);     // 80 MHz
  EXPECT_EQ(static_cast<uint8_t>(rt[30]), 0x92);  // MCS 9, 2 streams
}

// tshark's fields (`-e ...`, comma-separated, one line per frame) of the pcap at `path`, which
// is removed afterwards.
std::string TsharkFieldsOnce(const std::string& path, const std::string& fields) {
  const std::string command =
      "tshark -r " + path + " -T fields -E separator=, " + fields + " 2>/dev/null";
  std::string output;
  if (FILE* pipe = popen(command.c_str(), "r")) {
    char buffer[256];
    while (fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
    pclose(pipe);
  }
  std::remove(path.c_str());
  return output;
}

// What Wireshark's dissector makes of them: the oracle for the field layout.
TEST(PcapWriter, TsharkDecodesMcsBandwidthAndGi) {
  if (std::system("tshark --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "no tshark";
  char path[] = "/tmp/pcap_writer_test_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  close(fd);
  {
    std::ofstream out(path, std::ios::binary);
    out << PcapFileHeader() << EncodePcapRecord(HtFrame(false), 0)
        << EncodePcapRecord(HtFrame(true), 1000) << EncodePcapRecord(DataFrame(), 2000);
  }
  const std::string output = TsharkFieldsOnce(
      path,
      "-e radiotap.mcs.index -e radiotap.mcs.bw -e radiotap.mcs.gi"
      " -e radiotap.vht.mcs.0 -e radiotap.vht.nss.0 -e radiotap.vht.bw -e radiotap.vht.gi"
      " -e wlan.fc.type_subtype -e wlan.qos.tid -e radiotap.datarate");
  // HT: MCS 7, 40 MHz (bw 1), short GI (1), QoS Data (0x0028), TID 0, and the rate Wireshark
  // derives from them: 150 Mb/s. VHT: MCS 9, 2 streams, 80 MHz (bw 4), long GI (0), TID 6. 802.11a:
  // Data (0x0020) at 54 Mb/s, no MCS fields.
  EXPECT_EQ(output,
            "7,1,1,,,,,0x0028,0,150\n"
            ",,,9,2,4,0,0x0028,6,\n"
            ",,,,,,,0x0020,,54\n");
}

// MPDUs of A-MPDUs carry radiotap's A-MPDU status field (reference, last-subframe flags) after
// the MCS field (HT) or before the VHT field (VHT); the Block Ack frames decode as such.
TEST(PcapWriter, TsharkDecodesAmpduReferenceAndBlockAckFrames) {
  if (std::system("tshark --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "no tshark";
  char path[] = "/tmp/pcap_writer_test_XXXXXX";
  const int fd = mkstemp(path);
  ASSERT_GE(fd, 0);
  close(fd);
  AirFrame ht_first = HtFrame(false), ht_last = HtFrame(false), vht = HtFrame(true);
  ht_first.tx.ampdu_reference = ht_last.tx.ampdu_reference = 5;
  ht_last.tx.ampdu_last = true;
  ht_last.tx.sequence_number = 1;
  vht.tx.ampdu_reference = 7;
  AirFrame block_ack = DataFrame(), block_ack_req = DataFrame(), addba = DataFrame();
  block_ack.tx.kind = mac::FrameKind::kBlockAck;
  block_ack.tx.ba_bitmap = 0x3;
  block_ack_req.tx.kind = mac::FrameKind::kBlockAckReq;
  addba.tx.kind = mac::FrameKind::kAction;
  for (const AirFrame* f : {&block_ack, &block_ack_req, &addba}) {
    EXPECT_EQ(Encode80211Mpdu(*f).size(),
              f == &block_ack ? 32u : (f == &block_ack_req ? 24u : 37u));
  }
  {
    std::ofstream out(path, std::ios::binary);
    out << PcapFileHeader() << EncodePcapRecord(ht_first, 0) << EncodePcapRecord(ht_last, 0)
        << EncodePcapRecord(vht, 1000) << EncodePcapRecord(block_ack, 2000)
        << EncodePcapRecord(block_ack_req, 3000) << EncodePcapRecord(addba, 4000);
  }
  const std::string output = TsharkFieldsOnce(
      path,
      "-e radiotap.ampdu.reference -e radiotap.ampdu.flags.last"
      " -e radiotap.mcs.index -e radiotap.vht.mcs.0 -e wlan.seq -e wlan.fc.type_subtype");
  // DataFrame()'s sequence number is 5. BlockAck 0x0019, BlockAckReq 0x0018, Action 0x000d.
  EXPECT_EQ(output,
            "5,0,7,,5,0x0028\n"
            "5,1,7,,1,0x0028\n"
            "7,0,,9,5,0x0028\n"
            ",,,,,0x0019\n"
            ",,,,,0x0018\n"
            ",,,,5,0x000d\n");
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
