// losses.csv.gz and links.csv written from the medium's own trace: the hidden
// pair of mac_phy_sim's causes_test (A and C hidden from each other around B).
#include "run_formats/run_formats.h"

#include <gtest/gtest.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

namespace sitlnet::run_formats {
namespace {

constexpr MacAddress kBroadcast{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};

std::vector<uint8_t> Frame(const MacAddress& to, const MacAddress& from, int payload) {
  std::vector<uint8_t> f(14 + payload, 0);
  std::copy(to.bytes.begin(), to.bytes.end(), f.begin());
  std::copy(from.bytes.begin(), from.bytes.end(), f.begin() + 6);
  f[12] = 0x08;
  return f;
}

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string Gunzip(const std::string& path) {
  gzFile f = gzopen(path.c_str(), "rb");
  EXPECT_NE(f, nullptr);
  std::string text;
  char buffer[4096];
  int n;
  while ((n = gzread(f, buffer, sizeof buffer)) > 0) text.append(buffer, n);
  gzclose(f);
  return text;
}

TEST(LossLogTest, WritesEveryReceptionAboveTheNoiseFloorAndPerSecondLinks) {
  const std::string dir = ::testing::TempDir() + "/loss_log_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  mac::MediumConfig config;
  config.rate_mbps = 12;  // B -> A at -75 dBm (SNR 19 dB) decodes; 54 Mb/s would not.
  mac::Medium medium(config);
  medium.EnableTrace(true);
  medium.EnableCauses(true);
  const std::vector<MacAddress> macs = {RobotMac(0), RobotMac(1), RobotMac(2), RobotMac(3)};
  medium.AddStation(macs[0], {0, 0, 0});       // B
  medium.AddStation(macs[1], {-30, 0, 0});     // A
  medium.AddStation(macs[2], {30, 0, 0});      // C
  medium.AddStation(macs[3], {3000, 0, 0});    // Far: under the noise floor, never written.
  medium.SubmitFrame(1, Frame(kBroadcast, macs[1], 100), 0);
  medium.SubmitFrame(2, Frame(kBroadcast, macs[2], 100), 50 * kNsPerUs);
  // One second later B sends A a unicast frame alone: decoded and acknowledged.
  medium.SubmitFrame(0, Frame(macs[1], macs[0], 100), kNsPerS);
  medium.AdvanceTo(2 * kNsPerS, nullptr);
  std::vector<mac::TraceEvent> events;
  medium.DrainTrace(&events);
  {
    LossLog log(dir, macs, medium.phy().noise_floor_dbm, -82);
    for (const mac::TraceEvent& e : events) log.Add(e);
    log.Finish();
  }
  const std::vector<std::string> rows = Lines(Gunzip(dir + "/losses.csv.gz"));
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0], kLossHeader);
  auto find = [&](const std::string& prefix_from_to, const std::string& station_cause) {
    for (const std::string& r : rows) {
      if (r.find(prefix_from_to) != std::string::npos &&
          r.find(station_cause) != std::string::npos) {
        return true;
      }
    }
    return false;
  };
  EXPECT_TRUE(find(",1,-1,DATA,", ",0,collision,2,"));          // A's frame at B, C interfered.
  EXPECT_TRUE(find(",2,-1,DATA,", ",0,already_receiving,1,"));  // C's at B, locked on A.
  EXPECT_TRUE(find(",2,-1,DATA,", ",1,own_transmission,"));     // C's at A, A on the air.
  EXPECT_TRUE(find(",1,-1,DATA,", ",2,below_threshold,"));      // -84 dBm at C.
  EXPECT_TRUE(find(",0,1,DATA,", ",1,decoded,-1,"));
  EXPECT_TRUE(find(",1,0,ACK,", ",0,decoded,-1,"));
  for (const std::string& r : rows) EXPECT_EQ(r.find(",3,"), std::string::npos) << r;

  std::ifstream links_file(dir + "/links.csv");
  std::stringstream links_text;
  links_text << links_file.rdbuf();
  const std::vector<std::string> links = Lines(links_text.str());
  const std::vector<std::string> expected = {
      kLinkHeader,
      // The last two columns: the rate and no MCS (11a). B's and C's group frames go at 11a's
      // lowest basic rate, 6 Mb/s (IEEE 802.11-2016 10.6.6.2, as ns-3); A's unicast frame at the
      // medium's fixed 12 Mb/s (config.rate_mbps).
      "0,1,0,1,0,0.000,collision,1,6,",
      "0,1,2,1,0,0.000,range,1,6,",
      "0,2,0,1,0,0.000,already_receiving,1,6,",
      "0,2,1,1,0,0.000,own_transmission,1,6,",
      "1,0,1,1,1,1.000,none,0,12,",
  };
  EXPECT_EQ(links, expected);
}

// A drop row carries the frame's sequence number only if the frame was given one: a frame that
// met a full queue never was (mac::DropRecord::has_sequence_number).
TEST(LossLogTest, ADropRowHasASequenceNumberOnlyIfTheFrameWasGivenOne) {
  const std::string dir = ::testing::TempDir() + "/loss_log_drop_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const std::vector<MacAddress> macs = {RobotMac(0), RobotMac(1)};
  mac::TraceEvent never_numbered;
  never_numbered.drop = mac::DropRecord{};
  never_numbered.drop->time_ns = 1000;
  never_numbered.drop->destination = macs[1];
  mac::TraceEvent numbered = never_numbered;
  numbered.drop->time_ns = 2000;
  numbered.drop->reason = mac::DropReason::kRetryLimit;
  numbered.drop->sequence_number = 7;
  numbered.drop->has_sequence_number = true;
  {
    LossLog log(dir, macs, -94, -82);
    log.Add(never_numbered);
    log.Add(numbered);
    log.Finish();
  }
  const std::vector<std::string> rows = Lines(Gunzip(dir + "/losses.csv.gz"));
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].rfind("1000,0,1,DATA,,,0,", 0), 0u) << rows[1];
  EXPECT_EQ(rows[2].rfind("2000,0,1,DATA,7,,0,", 0), 0u) << rows[2];
}

// Issue 44, item 5: an 802.11n link's row names its MCS and rate, those of its last DATA frame
// in the second (here MCS 7 at 65 Mb/s, then MCS 4 at 39 Mb/s: IEEE 802.11-2016 Table 19-27).
TEST(LossLogTest, ALinksRowNamesTheRateAndMcsOfItsLastDataFrame) {
  const std::string dir = ::testing::TempDir() + "/loss_log_mcs_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const MacAddress a{{2, 0, 0, 0, 0, 1}}, b{{2, 0, 0, 0, 0, 2}};
  {
    LossLog log(dir, {a, b}, -95, -82);
    for (const auto& [start_ns, mcs, rate_mbps] :
         {std::tuple{1000, 7, 65.0}, std::tuple{2000000, 4, 39.0}}) {
      mac::TxRecord tx;
      tx.start_ns = start_ns;
      tx.end_ns = start_ns + 200000;
      tx.source = 0;
      tx.receiver = b;
      tx.transmitter = a;
      tx.mcs = mcs;
      tx.rate_mbps = rate_mbps;
      mac::RxRecord rx;
      rx.station = 1;
      rx.rx_power_dbm = -60;
      rx.cause = mac::RxCause::kDecoded;
      tx.receptions = {rx};
      log.Add(mac::TraceEvent{tx, std::nullopt});
    }
    log.Finish();
  }
  std::ifstream links_file(dir + "/links.csv");
  std::stringstream links_text;
  links_text << links_file.rdbuf();
  EXPECT_EQ(Lines(links_text.str()),
            (std::vector<std::string>{kLinkHeader, "0,0,1,2,2,1.000,none,0,39,4"}));
}

// summary.json's "delivery": B sends A (in the clear) and C (behind a 2 m wall, 9 dB + 0.8 dB
// of Sommer et al.'s model, still decoded at 12 Mb/s) one unicast frame each second. Every
// DATA transmission at the station it is for counts once, in the class of its path.
void ExpectClassesOfAClearAndAWalledLink(bool shadowing) {
  const std::string dir = ::testing::TempDir() + "/loss_log_class_test";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  mac::MediumConfig config;
  config.rate_mbps = 12;
  config.shadowing = shadowing;
  mac::Medium medium(config);
  medium.EnableTrace(true);
  medium.EnableCauses(true);
  const std::vector<MacAddress> macs = {RobotMac(0), RobotMac(1), RobotMac(2)};
  medium.AddStation(macs[0], {0, 0, 0});    // B
  medium.AddStation(macs[1], {-10, 0, 0});  // A, in the clear
  medium.AddStation(macs[2], {10, 0, 0});   // C, behind the wall
  medium.AddObstacle({{5, 0, 0}, {2, 20, 20}, 0});
  for (int second = 0; second < 3; ++second) {
    medium.SubmitFrame(0, Frame(macs[1], macs[0], 100), second * kNsPerS);
    medium.SubmitFrame(0, Frame(macs[2], macs[0], 100), second * kNsPerS + 100 * kNsPerMs);
  }
  medium.AdvanceTo(4 * kNsPerS, nullptr);
  std::vector<mac::TraceEvent> events;
  medium.DrainTrace(&events);
  LossLog log(dir, macs, medium.phy().noise_floor_dbm, -82);
  for (const mac::TraceEvent& e : events) log.Add(e);
  log.Finish();
  const DeliveryByLinkClass& by_class = log.delivery_by_link_class();
  EXPECT_EQ(by_class.line_of_sight.frames, 3u);
  EXPECT_EQ(by_class.line_of_sight.delivered, 3u);
  EXPECT_EQ(by_class.obstructed.frames, 3u);
  EXPECT_EQ(by_class.obstructed.delivered, 3u);
}

// The class is the geometry's, not the loss model's: with obstacle shadowing off, the wall
// takes no loss and C decodes every frame, yet its path is obstructed.
TEST(LossLogTest, CountsDeliveriesByLineOfSightAndObstructedLinks) {
  for (const bool shadowing : {true, false}) {
    SCOPED_TRACE(shadowing ? "shadowing" : "no shadowing");
    ExpectClassesOfAClearAndAWalledLink(shadowing);
  }
}

}  // namespace
}  // namespace sitlnet::run_formats
