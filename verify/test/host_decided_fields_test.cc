// WithoutHostDecidedFields on frames built by hand from the layouts it parses: pcap records
// (libpcap's file format), a radiotap header, an 802.11 data header (IEEE 802.11-2016 9.3.2.1),
// LLC/SNAP, IPv4 (RFC 791), UDP (RFC 768) and MAVLink 2 (its serialization spec). The oracle is
// which bytes those fields occupy.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

void Le32(std::string* out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<char>(v >> (8 * i)));
}
void Be16(std::string* out, uint16_t v) {
  out->push_back(static_cast<char>(v >> 8));
  out->push_back(static_cast<char>(v));
}

struct UdpFrame {
  uint16_t ip_id = 0x1234, ip_checksum = 0xbeef;
  uint16_t source_port = 14550, destination_port = 40123;  // The second is ephemeral.
  uint16_t udp_checksum = 0x7777;
  uint32_t fcs = 0xdeadbeef;
  std::string payload = "MAVLINK";
  bool qos = false;  // A QoS Data frame (802.11n/ac, or a/b/g with radio.qos): 2 more header bytes.
};

// A pcap with one record: radiotap (8 bytes, no fields), 802.11 data header (24 bytes), LLC/SNAP
// for IPv4, a 20-byte IPv4 header, UDP, the payload, the FCS.
std::string Capture(const UdpFrame& f) {
  std::string frame = std::string("\0\0\x08\0\0\0\0\0", 8);  // radiotap v0, length 8
  frame += std::string(f.qos ? "\x88\x02" : "\x08\x02", 2) + std::string(22, '\x11');  // addresses
  if (f.qos) frame += std::string("\x06\x00", 2);  // QoS Control: TID 6 (voice)
  frame += std::string("\xaa\xaa\x03\x00\x00\x00\x08\x00", 8);
  const uint16_t ip_length = static_cast<uint16_t>(20 + 8 + f.payload.size());
  frame += "\x45";
  frame += '\0';
  Be16(&frame, ip_length);
  Be16(&frame, f.ip_id);
  frame += std::string("\x40\x00\x40\x11", 4);  // DF, TTL 64, UDP
  Be16(&frame, f.ip_checksum);
  frame += std::string("\x0a\x00\x00\x01\x0a\x00\x00\x02", 8);
  Be16(&frame, f.source_port);
  Be16(&frame, f.destination_port);
  Be16(&frame, static_cast<uint16_t>(8 + f.payload.size()));
  Be16(&frame, f.udp_checksum);
  frame += f.payload;
  Le32(&frame, f.fcs);
  std::string pcap(24, '\0');  // The global header: not parsed.
  Le32(&pcap, 1);              // ts_sec
  Le32(&pcap, 500000);         // ts_usec
  Le32(&pcap, static_cast<uint32_t>(frame.size()));
  Le32(&pcap, static_cast<uint32_t>(frame.size()));
  return pcap + frame;
}

TEST(HostDecidedFieldsTest, MasksTheFieldsKernelsDrawAndNothingElse) {
  UdpFrame first, second;
  second.ip_id = 0x9abc;
  second.ip_checksum = 0x1111;
  second.destination_port = 51000;
  second.udp_checksum = 0x2222;
  second.fcs = 0x01020304;
  ASSERT_NE(Capture(first), Capture(second));
  EXPECT_EQ(WithoutHostDecidedFields(Capture(first)), WithoutHostDecidedFields(Capture(second)));

  UdpFrame other_payload = first;
  other_payload.payload = "MAVLINX";
  EXPECT_NE(WithoutHostDecidedFields(Capture(first)),
            WithoutHostDecidedFields(Capture(other_payload)));
  UdpFrame fixed_port = first;  // Below 32768: chosen by the program, kept.
  fixed_port.source_port = 14551;
  EXPECT_NE(WithoutHostDecidedFields(Capture(first)),
            WithoutHostDecidedFields(Capture(fixed_port)));
}

// A MAVLink 2 SYS_STATUS frame (msgid 1) whose health word is `health`, with checksum `crc`.
std::string SysStatus(uint32_t health, uint16_t crc, uint8_t msgid = 1) {
  std::string frame("\xfd\x1f\x00\x00\x15\x01\x01", 7);  // length 31, seq 21, sys 1, comp 1
  frame += static_cast<char>(msgid);
  frame += std::string(2, '\0');
  std::string payload(31, '\x5a');
  for (int i = 0; i < 4; ++i) payload[8 + i] = static_cast<char>(health >> (8 * i));
  frame += payload;
  frame += static_cast<char>(crc);
  frame += static_cast<char>(crc >> 8);
  return frame;
}

// CI failure of ArduCopterReproducibilityTest: SYS_STATUS health 0x44119c0b in one run and
// 0x45119c0b in the other (the logger bit, 0x01000000), the MAVLink checksum following.
TEST(HostDecidedFieldsTest, MasksArduCoptersLoggerHealthBitAndItsChecksumOnly) {
  UdpFrame first, second;
  first.payload = SysStatus(0x44119c0b, 0x3ee8) + SysStatus(0x44119c0b, 0x3ee8);
  second.payload = SysStatus(0x44119c0b, 0x3ee8) + SysStatus(0x45119c0b, 0x0984);
  EXPECT_EQ(WithoutHostDecidedFields(Capture(first)), WithoutHostDecidedFields(Capture(second)));
  UdpFrame other_health = first;  // Another sensor's bit (GPS, 0x20): kept.
  other_health.payload = SysStatus(0x44119c0b, 0x3ee8) + SysStatus(0x44119c2b, 0x0984);
  EXPECT_NE(WithoutHostDecidedFields(Capture(first)),
            WithoutHostDecidedFields(Capture(other_health)));
  UdpFrame not_sys_status = first;  // The same bytes in message 2 (SYSTEM_TIME): kept.
  not_sys_status.payload = SysStatus(0x44119c0b, 0x3ee8, 2) + SysStatus(0x45119c0b, 0x0984, 2);
  UdpFrame not_sys_status_other = not_sys_status;
  not_sys_status_other.payload = SysStatus(0x44119c0b, 0x3ee8, 2) + SysStatus(0x44119c0b, 0x3ee8, 2);
  EXPECT_NE(WithoutHostDecidedFields(Capture(not_sys_status)),
            WithoutHostDecidedFields(Capture(not_sys_status_other)));
}

// The same fields sit two bytes further in a QoS Data frame (IEEE 802.11-2016 9.3.2.1).
TEST(HostDecidedFieldsTest, MasksTheSameFieldsInQosDataFrames) {
  UdpFrame first, second;
  first.qos = second.qos = true;
  second.ip_id = 0x9abc;
  second.destination_port = 51000;
  second.udp_checksum = 0x2222;
  second.fcs = 0x01020304;
  EXPECT_EQ(WithoutHostDecidedFields(Capture(first)), WithoutHostDecidedFields(Capture(second)));
  UdpFrame other_payload = first;
  other_payload.payload = "MAVLINX";
  EXPECT_NE(WithoutHostDecidedFields(Capture(first)),
            WithoutHostDecidedFields(Capture(other_payload)));
}

TEST(HostDecidedFieldsTest, ATruncatedCaptureIsLeftAsItIs) {
  const std::string cut = Capture(UdpFrame{}).substr(0, 50);
  EXPECT_EQ(WithoutHostDecidedFields(cut), cut);
}

}  // namespace
}  // namespace sitlnet::verify
