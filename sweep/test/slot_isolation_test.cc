// Job slots: names within the scenario's rule, ctl subnets that never overlap, ports apart.
#include <gtest/gtest.h>

#include <regex>

#include "common/common.h"
#include "scenario/scenario.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

TEST(SlotIsolationTest, GivesEachSlotItsOwnNameCtlSubnetAndPort) {
  constexpr int kSlots = 64;
  std::vector<proto::Scenario> specs(kSlots);
  for (int slot = 0; slot < kSlots; ++slot) IsolateForSlot(slot, 123456, &specs[slot]);
  EXPECT_EQ(specs[0].name(), "sw3456_0");
  EXPECT_EQ(specs[2].addresses().wlan_subnet(), "10.77.0.0/24");  // Kept: inside robots only.
  EXPECT_EQ(specs[2].addresses().ctl_subnet(), "10.80.0.0/16");   // Moved 2 sizes up.
  EXPECT_EQ(specs[2].addresses().physics_port(), 9502u);
  std::vector<Ipv4Prefix> subnets;
  for (int a = 0; a < kSlots; ++a) {
    subnets.push_back(*ParseIpv4Prefix(specs[a].addresses().ctl_subnet()));
    for (int b = 0; b < a; ++b) {
      EXPECT_NE(specs[a].name(), specs[b].name());
      EXPECT_NE(specs[a].addresses().physics_port(), specs[b].addresses().physics_port());
    }
  }
  for (size_t a = 0; a < subnets.size(); ++a) {
    for (size_t b = 0; b < a; ++b) {
      EXPECT_FALSE(subnets[a].Overlaps(subnets[b]))
          << FormatIpv4Prefix(subnets[a]) << " " << FormatIpv4Prefix(subnets[b]);
    }
  }
}

TEST(SlotIsolationTest, NamesKeepTheScenarioNameRule) {
  proto::Scenario spec;
  IsolateForSlot(999, 4294967295u, &spec);
  EXPECT_LE(static_cast<int>(spec.name().size()), kMaxScenarioNameLength);
  EXPECT_TRUE(std::regex_match(spec.name(), std::regex("[a-z0-9_]{1,10}"))) << spec.name();
  EXPECT_THROW(IsolateForSlot(1000, 1, &spec), Error);
}

TEST(SlotIsolationTest, RefusesSubnetsPastTheAddressSpace) {
  proto::Scenario spec;
  spec.mutable_addresses()->set_ctl_subnet("255.255.255.0/24");
  EXPECT_NO_THROW(IsolateForSlot(0, 1, &spec));
  spec.mutable_addresses()->set_ctl_subnet("255.255.255.0/24");
  try {
    IsolateForSlot(1, 1, &spec);
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("addresses.ctl_subnet \"255.255.255.0/24\": job slot 1"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace sitlnet::sweep
