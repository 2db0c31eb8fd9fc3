// flocker's command line: every VAT flag sets the parameter its usage and docs/case-study.md name
// (and no other), and bad input exits 2 with one line naming the flag.
#include "robot_images/flocker/flocker_options.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace sitlnet::flocker {
namespace {

Options Parse(std::vector<std::string> args) {
  args.insert(args.begin(), "flocker");
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  return ParseOptions(static_cast<int>(argv.size()), argv.data());
}

// The flag of each symbol, as docs/case-study.md's parameter table and `flocker --help` give them.
struct VatFlag {
  const char* flag;
  double FlockingParams::*field;
};
const VatFlag kVatFlags[] = {
    {"--flock-speed-m-s", &FlockingParams::flock_speed_m_s},            // v_flock
    {"--max-speed-m-s", &FlockingParams::max_speed_m_s},                // v_max
    {"--migration-speed-m-s", &FlockingParams::migration_speed_m_s},    // v_mig
    {"--repulsion-range-m", &FlockingParams::repulsion_range_m},        // r0_rep
    {"--repulsion-gain", &FlockingParams::repulsion_gain_1_s},          // p_rep
    {"--attraction-range-m", &FlockingParams::attraction_range_m},      // r0_att
    {"--attraction-gain", &FlockingParams::attraction_gain_1_s},        // p_att
    {"--friction-range-m", &FlockingParams::friction_range_m},          // r0_frict
    {"--friction-coefficient", &FlockingParams::friction_coefficient},  // C_frict
    {"--friction-slack-m-s", &FlockingParams::friction_slack_m_s},      // v_frict
    {"--friction-accel-m-s2", &FlockingParams::friction_accel_m_s2},    // a_frict
    {"--friction-gain", &FlockingParams::friction_gain_1_s},            // p_frict
    {"--shill-range-m", &FlockingParams::shill_range_m},                // r0_shill
    {"--shill-speed-m-s", &FlockingParams::shill_speed_m_s},            // v_shill
    {"--shill-accel-m-s2", &FlockingParams::shill_accel_m_s2},          // a_shill
    {"--shill-gain", &FlockingParams::shill_gain_1_s},                  // p_shill
};

TEST(FlockerOptionsTest, EachVatFlagSetsItsParameterAndNoOther) {
  const FlockingParams defaults;
  for (const VatFlag& set : kVatFlags) {
    const Options options = Parse({set.flag, "7.25"});
    for (const VatFlag& other : kVatFlags) {
      const double expected = &set == &other ? 7.25 : defaults.*other.field;
      EXPECT_EQ(options.flocking.*other.field, expected) << set.flag << " -> " << other.flag;
    }
  }
}

TEST(FlockerOptionsTest, RobotFlagsAreRead) {
  const Options options = Parse({"--target", "120,-4.5", "--beacon-port", "47001", "--device",
                                 "wlan1", "--airframe", "mass_kg: 2", "--broadcast-hz", "5"});
  EXPECT_EQ(options.target_m, Vec2(120, -4.5));
  EXPECT_EQ(options.beacon_port, 47001);
  EXPECT_EQ(options.device, "wlan1");
  EXPECT_EQ(options.airframe_text, "mass_kg: 2");
  EXPECT_EQ(options.broadcast_hz, 5);
  EXPECT_EQ(options.tos, 0) << "beacons at best effort unless asked";
}

TEST(FlockerOptionsTest, TosIsATosByteInDecimalOrHex) {
  EXPECT_EQ(Parse({"--tos", "0xc0"}).tos, 0xc0);
  EXPECT_EQ(Parse({"--tos", "184"}).tos, 184);
  EXPECT_EQ(Parse({"--tos", "0"}).tos, 0);
  EXPECT_EQ(Parse({"--tos", "010"}).tos, 10) << "decimal, not octal";
}

TEST(FlockerOptionsTest, BadInputExitsTwoNamingTheFlag) {
  const auto exits_2 = ::testing::ExitedWithCode(2);
  EXPECT_EXIT(Parse({"--no-such-flag", "1"}), exits_2, "flocker: unknown flag --no-such-flag");
  EXPECT_EXIT(Parse({"--repulsion-gain", "fast"}), exits_2,
              "flocker: --repulsion-gain: \"fast\" is not a number");
  EXPECT_EXIT(Parse({"--shill-gain", "nan"}), exits_2, "--shill-gain: \"nan\" is not a number");
  EXPECT_EXIT(Parse({"--target", "120"}), exits_2, "--target wants X,Y");
  EXPECT_EXIT(Parse({"--beacon-port", "70000"}), exits_2, "--beacon-port: 1..65535");
  EXPECT_EXIT(Parse({"--altitude-m"}), exits_2, "--altitude-m needs a value");
  EXPECT_EXIT(Parse({"--tos", "256"}), exits_2, "--tos: \"256\" is not a TOS byte");
  EXPECT_EXIT(Parse({"--tos", "-1"}), exits_2, "--tos: \"-1\" is not a TOS byte");
  EXPECT_EXIT(Parse({"--tos", "voice"}), exits_2, "--tos: \"voice\" is not a TOS byte");
  EXPECT_EXIT(Parse({"--broadcast-hz", "0"}), exits_2, "--broadcast-hz must be at least 0.001");
  // A period in ns past int64's end (1e9 / 1e-20 Hz) would be undefined behaviour in the cast.
  EXPECT_EXIT(Parse({"--broadcast-hz", "1e-20"}), exits_2, "--broadcast-hz must be at least");
  EXPECT_EXIT(Parse({"--log-period-s", "1e300"}), exits_2,
              "--log-period-s must be in \\[0, 1e6\\]");
  EXPECT_EXIT(Parse({"--neighbour-timeout-s", "-1"}), exits_2, "--neighbour-timeout-s must be in");
  EXPECT_EXIT(Parse({"--max-speed-m-s", "-1"}), exits_2, "--max-speed-m-s must be > 0");
  EXPECT_EXIT(Parse({"--help"}), ::testing::ExitedWithCode(0), "");
}

}  // namespace
}  // namespace sitlnet::flocker
