// The autopilot modes read from medium.pcap against node-mavlink, an implementation sitlnet did
// not write (tests/node_mavlink/copter_heartbeats.cjs): every ArduCopter mode of its CopterMode
// enum, encoded there, carried in a UDP datagram of a robot's 802.11 frame as sitlnet's pcap
// writer records it, must read back as the enum's own name. Skipped when node or node-mavlink
// is missing, except under CI=true, where that is a failure.
#include "view/air_modes.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <sstream>

#include "tapbridge/tapbridge.h"
#include "view/live_modes.h"
#include "view/replay_json.h"
#include "view/test/run_folder_fixture.h"

namespace sitlnet::view {
namespace {

std::string NodeMavlinkDir() {
  const char* source = std::getenv("SITLNET_SOURCE_DIR");
  return std::string(source ? source : ".") + "/tests/node_mavlink";
}

using Heartbeats = std::vector<std::pair<std::vector<uint8_t>, std::string>>;

// (frame bytes, expected mode or "-") per line of copter_heartbeats.cjs; empty if it failed.
Heartbeats RunCopterHeartbeats() {
  Heartbeats heartbeats;
  FILE* pipe = popen(("node " + NodeMavlinkDir() + "/copter_heartbeats.cjs").c_str(), "r");
  if (pipe == nullptr) return heartbeats;
  std::string out;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  if (pclose(pipe) != 0) return {};
  std::istringstream lines(out);
  std::string hex, name;
  while (lines >> hex >> name) {
    std::vector<uint8_t> bytes;
    for (size_t i = 0; i + 1 < hex.size(); i += 2) {
      bytes.push_back(static_cast<uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
    }
    heartbeats.emplace_back(std::move(bytes), name);
  }
  return heartbeats;
}

// An Ethernet frame from robot `robot` carrying `payload` in an IPv4 UDP datagram (14550).
std::vector<uint8_t> UdpFrame(int robot, const std::vector<uint8_t>& payload) {
  const MacAddress mac = RobotMac(robot);
  std::vector<uint8_t> frame = {0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
  frame.insert(frame.end(), mac.bytes.begin(), mac.bytes.end());
  frame.insert(frame.end(), {0x08, 0x00});
  const size_t udp_bytes = 8 + payload.size();
  const size_t ip_bytes = 20 + udp_bytes;
  frame.insert(frame.end(), {0x45,
                             0,
                             static_cast<uint8_t>(ip_bytes >> 8),
                             static_cast<uint8_t>(ip_bytes),
                             0,
                             0,
                             0x40,
                             0,
                             64,
                             17,
                             0,
                             0,
                             10,
                             0,
                             0,
                             static_cast<uint8_t>(robot + 1),
                             10,
                             0,
                             0,
                             255});
  frame.insert(frame.end(), {0x38, 0xd6, 0x38, 0xd6, static_cast<uint8_t>(udp_bytes >> 8),
                             static_cast<uint8_t>(udp_bytes), 0, 0});
  frame.insert(frame.end(), payload.begin(), payload.end());
  return frame;
}

// The pcap record of robot `robot`'s DATA frame carrying `payload`, started at `start_ns`.
std::string Record(int robot, TimeNs start_ns, const std::vector<uint8_t>& payload,
                   bool retry = false) {
  tapbridge::AirFrame air;
  air.tx.start_ns = start_ns;
  air.tx.end_ns = start_ns + kNsPerMs;
  air.tx.source = robot;
  air.tx.retry = retry;
  air.tx.rate_mbps = 6;
  air.tx.receiver = MacAddress{{0xff, 0xff, 0xff, 0xff, 0xff, 0xff}};
  air.tx.transmitter = RobotMac(robot);
  air.tx.ethernet_frame = std::make_shared<const std::vector<uint8_t>>(UdpFrame(robot, payload));
  // Realtime pcaps carry wall-clock dates: the reader must take the simulated time (TSFT).
  return tapbridge::EncodePcapRecord(air, 1'700'000'000 * kNsPerS);
}

class AirModesTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const bool have_node = std::system("node --version >/dev/null 2>&1") == 0;
    const bool have_package =
        std::filesystem::exists(NodeMavlinkDir() + "/node_modules/node-mavlink/package.json");
    if (!have_node || !have_package) {
      const std::string why = !have_node ? "node is not installed"
                                         : "node-mavlink is not installed in " + NodeMavlinkDir() +
                                               "/node_modules (scripts/setup installs it)";
      const char* ci = std::getenv("CI");
      if (ci != nullptr && std::string(ci) == "true") FAIL() << why;
      GTEST_SKIP() << why;
    }
    static const Heartbeats heartbeats = RunCopterHeartbeats();  // Node once per process.
    heartbeats_ = heartbeats;
    ASSERT_GT(heartbeats_.size(), 20u) << "copter_heartbeats.cjs printed no modes";
  }
  // node-mavlink's HEARTBEAT of the mode `name`.
  std::vector<uint8_t> Named(const std::string& name) const {
    for (const auto& [bytes, mode] : heartbeats_) {
      if (mode == name) return bytes;
    }
    ADD_FAILURE() << "no HEARTBEAT in " << name;
    return {};
  }
  Heartbeats heartbeats_;
};

TEST_F(AirModesTest, EveryCopterModeOfNodeMavlinkReadsBackByItsName) {
  // Robot 1 sends each HEARTBEAT, one a second. Between them: a retransmission of another mode
  // (not read: it repeats a frame), the same HEARTBEAT from a MAC of no robot (index 5 of 2),
  // and a ground station's (no autopilot mode).
  std::string pcap = tapbridge::PcapFileHeader();
  std::vector<std::string> expected;
  for (size_t i = 0; i < heartbeats_.size(); ++i) {
    const auto& [bytes, name] = heartbeats_[i];
    const TimeNs start_ns = static_cast<TimeNs>(i + 1) * kNsPerS + 123 * kNsPerUs;
    pcap += Record(1, start_ns, bytes);
    if (name != "-") expected.push_back(name);
    const auto& other = heartbeats_[(i + 3) % heartbeats_.size()].first;
    pcap += Record(1, start_ns + kNsPerMs, other, /*retry=*/true);
    pcap += Record(5, start_ns + 2 * kNsPerMs, other);
  }
  AirModeReader reader(2);
  for (size_t at = 0; at < pcap.size(); at += 7) {  // As a file still being written.
    const size_t size = std::min<size_t>(7, pcap.size() - at);
    reader.Push(reinterpret_cast<const uint8_t*>(pcap.data()) + at, size);
  }
  ASSERT_EQ(reader.changes().size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(reader.changes()[i].mode, expected[i]);
    EXPECT_EQ(reader.changes()[i].robot, 1);
    EXPECT_EQ(reader.changes()[i].time_ns, static_cast<TimeNs>(i + 1) * kNsPerS + 123 * kNsPerUs);
  }
  EXPECT_EQ(reader.Latest(1)->mode, expected.back());
  EXPECT_EQ(reader.Latest(0), nullptr);
}

// The live view reads medium.pcap while the run writes it: a record cut in two shows once whole.
TEST_F(AirModesTest, TheLiveViewReadsWhatWasAppendedSinceItsLastRead) {
  const std::string dir = ::testing::TempDir() + "/air_modes_live";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/medium.pcap";
  std::filesystem::remove(path);
  LiveModes modes(dir, 2);
  modes.Update();  // No file yet: no modes.
  EXPECT_TRUE(modes.Latest().empty());
  const std::string guided = Record(1, kNsPerS, Named("GUIDED"));
  const std::string land = Record(1, 2 * kNsPerS, Named("LAND"));
  testing::WriteFile(path, tapbridge::PcapFileHeader() + guided.substr(0, 20));
  modes.Update();
  EXPECT_TRUE(modes.Latest().empty());
  const auto append = [&](const std::string& bytes) {
    FILE* file = std::fopen(path.c_str(), "ab");
    ASSERT_NE(file, nullptr);
    std::fwrite(bytes.data(), 1, bytes.size(), file);
    std::fclose(file);
  };
  append(guided.substr(20));
  modes.Update();
  ASSERT_EQ(modes.Latest().size(), 1u);
  EXPECT_EQ(modes.Latest()[0].mode, "GUIDED");
  append(land);
  modes.Update();
  ASSERT_EQ(modes.Latest().size(), 1u);
  EXPECT_EQ(modes.Latest()[0].mode, "LAND");
  EXPECT_EQ(modes.Latest()[0].time_ns, 2 * kNsPerS);

  // Not a pcap of sitlnet's: said once, and the modes stay as they were.
  LiveModes broken(dir, 2);
  testing::WriteFile(path, "not a pcap file, but long enough to have a header");
  ::testing::internal::CaptureStderr();
  broken.Update();
  broken.Update();
  EXPECT_EQ(::testing::internal::GetCapturedStderr(),
            "sitlnet run: live view: \"" + path + "\": not a pcap file of sitlnet's "
            "(nanosecond pcap, radiotap link type); no autopilot modes shown\n");
  EXPECT_TRUE(broken.Latest().empty());
}

TEST_F(AirModesTest, ReplayListsARunFoldersModeChanges) {
  const std::string dir = testing::WriteRunFolder("air_modes_replay", "");
  // GUIDED twice (one change), then LAND.
  testing::WriteFile(dir + "/medium.pcap",
                     tapbridge::PcapFileHeader() + Record(0, kNsPerS, Named("GUIDED")) +
                         Record(0, 2 * kNsPerS, Named("GUIDED")) +
                         Record(0, 3 * kNsPerS + 500 * kNsPerMs, Named("LAND")));
  EXPECT_EQ(ModesJson(LoadReplayedRun(dir)), "{\"modes\":[[1,0,\"GUIDED\"],[3.5,0,\"LAND\"]]}");
  testing::WriteFile(dir + "/medium.pcap", "not a pcap file, but long enough to have a header");
  try {
    LoadReplayedRun(dir);
    ADD_FAILURE() << "no error";
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "\"" + dir +
                  "/medium.pcap\": not a pcap file of sitlnet's (nanosecond pcap, "
                  "radiotap link type)");
  }
}

}  // namespace
}  // namespace sitlnet::view
