// sitlnet's MAVLink 2 against node-mavlink, an implementation sitlnet did not write
// (tests/node_mavlink/, installed by scripts/setup): node-mavlink decodes every message the PX4
// link sends, with CRC and CRC_EXTRA checked, and encodes the HIL_ACTUATOR_CONTROLS (with PX4's
// HEARTBEAT and COMMAND_LONG) that sitlnet decodes. Skipped when node or the package is missing,
// except under CI=true, where that is a failure.
#include <gtest/gtest.h>
#include <poll.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "mavlink/mavlink.h"
#include "physics_mujoco/px4_simulator_link.h"
#include "physics_mujoco/test/fake_px4.h"

namespace sitlnet::physics {
namespace {

std::string ScriptDir() {
  const char* source = std::getenv("SITLNET_SOURCE_DIR");
  return std::string(source ? source : ".") + "/tests/node_mavlink";
}

bool Ci() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

// Runs a shell command and returns its standard output; fails the test on a non-zero exit.
std::string RunCommand(const std::string& command) {
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr) {
    ADD_FAILURE() << "popen " << command;
    return {};
  }
  std::string out;
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) out.append(buffer, n);
  EXPECT_EQ(pclose(pipe), 0) << command << "\n" << out;
  return out;
}

class MavlinkNodeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const bool have_node = std::system("node --version >/dev/null 2>&1") == 0;
    const bool have_package =
        std::filesystem::exists(ScriptDir() + "/node_modules/node-mavlink/package.json");
    if (!have_node || !have_package) {
      const std::string why = !have_node ? "node is not installed"
                                         : "node-mavlink is not installed in " + ScriptDir() +
                                               "/node_modules (scripts/setup installs it)";
      if (Ci()) FAIL() << why;
      GTEST_SKIP() << why;
    }
  }
};

// "MSG <id> <name> seq=.. k=v ..." -> {"id": .., "name": .., "k": "v", ...}
std::vector<std::map<std::string, std::string>> ParseMessages(const std::string& text,
                                                              std::string* counts) {
  std::vector<std::map<std::string, std::string>> messages;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line);
    std::string kind;
    words >> kind;
    if (kind == "COUNTS") {
      *counts = line;
      continue;
    }
    std::map<std::string, std::string> fields;
    words >> fields["id"] >> fields["name"];
    std::string word;
    while (words >> word) {
      const size_t eq = word.find('=');
      fields[word.substr(0, eq)] = word.substr(eq + 1);
    }
    fields["kind"] = kind;
    messages.push_back(std::move(fields));
  }
  return messages;
}

// A float field decoded by node (a double printed exactly) equals what sitlnet packed.
void ExpectFloat(const std::map<std::string, std::string>& m, const std::string& name,
                 float value) {
  ASSERT_TRUE(m.count(name)) << name;
  EXPECT_EQ(static_cast<float>(std::stod(m.at(name))), value) << name;
}
void ExpectInt(const std::map<std::string, std::string>& m, const std::string& name,
               long long value) {
  ASSERT_TRUE(m.count(name)) << name;
  EXPECT_EQ(std::stoll(m.at(name)), value) << name;
}

// Connects to the link as PX4 would and returns everything the link sends for one Send():
// HEARTBEAT, HIL_SENSOR, HIL_GPS, HIL_STATE_QUATERNION.
std::vector<uint8_t> CaptureSend(const mavlink::HilSensor& sensor, const mavlink::HilGps& gps,
                                 const mavlink::HilStateQuaternion& truth) {
  const Ipv4 loopback{0x7F000001};
  Px4SimulatorLink link(loopback, 0, 1000, "node test");
  testing::FakePx4 px4(loopback, link.port());
  pollfd listen{link.listen_fd(), POLLIN, 0};
  EXPECT_EQ(poll(&listen, 1, 5000), 1);
  link.Poll();
  EXPECT_TRUE(link.connected());
  link.Send(sensor, &gps, &truth);
  px4.Receive(mavlink::kHilStateQuaternionId);  // the last of the four
  return px4.received();
}

TEST_F(MavlinkNodeTest, NodeMavlinkDecodesEveryMessageSitlnetSends) {
  mavlink::HilSensor sensor;
  sensor.time_usec = 1234567890123;
  sensor.xacc = 0.125f;
  sensor.yacc = -0.5f;
  sensor.zacc = -9.80665f;
  sensor.xgyro = 0.01f;
  sensor.ygyro = -0.02f;
  sensor.zgyro = 0.3f;
  sensor.xmag = 0.21523f;
  sensor.ymag = 0.01334f;
  sensor.zmag = 0.4329f;
  sensor.abs_pressure = 955.4321f;
  sensor.pressure_alt = 500.25f;
  sensor.temperature = 11.9f;
  sensor.fields_updated = mavlink::kSensorUpdatedAccelGyro | mavlink::kSensorUpdatedMag |
                          mavlink::kSensorUpdatedBaro;  // id 0: the extension is truncated
  mavlink::HilGps gps;
  gps.time_usec = 1234567890123;
  gps.fix_type = 3;
  gps.lat = 473977420;
  gps.lon = -85455940;
  gps.alt = 488250;
  gps.eph = 100;
  gps.epv = 150;
  gps.vel = 500;
  gps.vn = -300;
  gps.ve = -400;
  gps.vd = 50;
  gps.cog = 23313;
  gps.satellites_visible = 10;
  mavlink::HilStateQuaternion truth;
  truth.time_usec = 1234567890123;
  truth.attitude_quaternion = {0.5f, -0.5f, 0.5f, 0.5f};
  truth.rollspeed = 0.1f;
  truth.pitchspeed = -0.2f;
  truth.yawspeed = 0.3f;
  truth.lat = 473977420;
  truth.lon = -85455940;
  truth.alt = 488250;
  truth.vx = -300;
  truth.vy = -400;
  truth.vz = 50;
  truth.ind_airspeed = 502;
  truth.true_airspeed = 502;
  truth.xacc = 12;
  truth.yacc = -34;
  truth.zacc = -1000;

  const std::vector<uint8_t> bytes = CaptureSend(sensor, gps, truth);
  const std::string path =
      (std::filesystem::temp_directory_path() / ("sitlnet_mavlink_" + std::to_string(getpid())))
          .string();
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char*>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  const std::string out = RunCommand("node " + ScriptDir() + "/decode.cjs < " + path);
  std::filesystem::remove(path);

  std::string counts;
  const auto messages = ParseMessages(out, &counts);
  EXPECT_EQ(counts, "COUNTS valid=4 invalid=0 unknown=0") << out;
  ASSERT_EQ(messages.size(), 4u) << out;
  for (const auto& m : messages) {
    EXPECT_EQ(m.at("kind"), "MSG");
    ExpectInt(m, "sysid", 1);
    ExpectInt(m, "compid", 200);
  }
  for (size_t i = 0; i < messages.size(); ++i)
    ExpectInt(messages[i], "seq", static_cast<long long>(i));

  const auto& heartbeat = messages[0];
  EXPECT_EQ(heartbeat.at("name"), "HEARTBEAT");
  ExpectInt(heartbeat, "autopilot", 8);
  ExpectInt(heartbeat, "system_status", 4);
  ExpectInt(heartbeat, "mavlink_version", 3);

  const auto& s = messages[1];
  EXPECT_EQ(s.at("name"), "HIL_SENSOR");
  ExpectInt(s, "time_usec", 1234567890123);
  ExpectFloat(s, "xacc", sensor.xacc);
  ExpectFloat(s, "yacc", sensor.yacc);
  ExpectFloat(s, "zacc", sensor.zacc);
  ExpectFloat(s, "xgyro", sensor.xgyro);
  ExpectFloat(s, "ygyro", sensor.ygyro);
  ExpectFloat(s, "zgyro", sensor.zgyro);
  ExpectFloat(s, "xmag", sensor.xmag);
  ExpectFloat(s, "ymag", sensor.ymag);
  ExpectFloat(s, "zmag", sensor.zmag);
  ExpectFloat(s, "abs_pressure", sensor.abs_pressure);
  ExpectFloat(s, "diff_pressure", 0);
  ExpectFloat(s, "pressure_alt", sensor.pressure_alt);
  ExpectFloat(s, "temperature", sensor.temperature);
  ExpectInt(s, "fields_updated", 0x1BFF);
  ExpectInt(s, "id", 0);

  const auto& g = messages[2];
  EXPECT_EQ(g.at("name"), "HIL_GPS");
  ExpectInt(g, "time_usec", 1234567890123);
  ExpectInt(g, "fix_type", 3);
  ExpectInt(g, "lat", gps.lat);
  ExpectInt(g, "lon", gps.lon);
  ExpectInt(g, "alt", gps.alt);
  ExpectInt(g, "eph", 100);
  ExpectInt(g, "epv", 150);
  ExpectInt(g, "vel", 500);
  ExpectInt(g, "vn", -300);
  ExpectInt(g, "ve", -400);
  ExpectInt(g, "vd", 50);
  ExpectInt(g, "cog", 23313);
  ExpectInt(g, "satellites_visible", 10);
  ExpectInt(g, "id", 0);
  ExpectInt(g, "yaw", 0);

  const auto& q = messages[3];
  EXPECT_EQ(q.at("name"), "HIL_STATE_QUATERNION");
  ExpectInt(q, "time_usec", 1234567890123);
  EXPECT_EQ(q.at("attitude_quaternion"), "0.5,-0.5,0.5,0.5");
  ExpectFloat(q, "rollspeed", 0.1f);
  ExpectFloat(q, "pitchspeed", -0.2f);
  ExpectFloat(q, "yawspeed", 0.3f);
  ExpectInt(q, "lat", truth.lat);
  ExpectInt(q, "lon", truth.lon);
  ExpectInt(q, "alt", truth.alt);
  ExpectInt(q, "vx", -300);
  ExpectInt(q, "vy", -400);
  ExpectInt(q, "vz", 50);
  ExpectInt(q, "ind_airspeed", 502);
  ExpectInt(q, "true_airspeed", 502);
  ExpectInt(q, "xacc", 12);
  ExpectInt(q, "yacc", -34);
  ExpectInt(q, "zacc", -1000);
}

std::vector<uint8_t> FromHex(const std::string& hex) {
  std::vector<uint8_t> bytes;
  for (size_t i = 0; i + 1 < hex.size(); i += 2) {
    bytes.push_back(static_cast<uint8_t>(std::stoi(hex.substr(i, 2), nullptr, 16)));
  }
  return bytes;
}

TEST_F(MavlinkNodeTest, SitlnetDecodesWhatNodeMavlinkEncodes) {
  const std::string out =
      RunCommand("node " + ScriptDir() +
                 "/encode.cjs 987654321 129 1 0.5 0.25 0.125 1 0.75 0 0 0 0 0 0 0 0 "
                 "0 0 0");
  std::vector<uint8_t> stream;
  std::istringstream lines(out);
  std::string line;
  while (std::getline(lines, line)) {
    const std::vector<uint8_t> bytes = FromHex(line);
    stream.insert(stream.end(), bytes.begin(), bytes.end());
  }
  mavlink::FrameParser parser;
  parser.Push(stream.data(), stream.size());
  std::vector<mavlink::ReceivedFrame> frames;
  mavlink::ReceivedFrame frame;
  while (parser.Next(&frame)) frames.push_back(frame);
  ASSERT_EQ(frames.size(), 3u) << out;
  EXPECT_EQ(parser.counters().bad_crc, 0u);
  EXPECT_EQ(parser.counters().bytes_skipped, 0u);

  mavlink::Heartbeat heartbeat;
  ASSERT_TRUE(mavlink::Unpack(frames[0], &heartbeat));
  EXPECT_EQ(heartbeat.autopilot, 12);
  EXPECT_EQ(heartbeat.type, 2);
  EXPECT_EQ(frames[1].message_id, mavlink::kCommandLongId);
  mavlink::HilActuatorControls controls;
  ASSERT_TRUE(mavlink::Unpack(frames[2], &controls));
  EXPECT_EQ(frames[2].header.system_id, 1);
  EXPECT_EQ(frames[2].header.sequence, 2);
  EXPECT_EQ(controls.time_usec, 987654321u);
  EXPECT_EQ(controls.mode, 129);
  EXPECT_EQ(controls.flags, 1u);
  const float expected[16] = {0.5f, 0.25f, 0.125f, 1, 0.75f};
  for (int i = 0; i < 16; ++i) EXPECT_EQ(controls.controls[i], expected[i]) << i;
}

}  // namespace
}  // namespace sitlnet::physics
