// Helpers for the tapbridge integration tests: a scenario brought up with the
// CLI under a unique name, the medium daemon as a child process, programs run
// inside robots (processes: test_util.h), 802.11 timing computed from the standard (the oracles).
#ifndef SITLNET_TESTS_INTEGRATION_TAPBRIDGE_TEST_UTIL_H_
#define SITLNET_TESTS_INTEGRATION_TAPBRIDGE_TEST_UTIL_H_

#include <gtest/gtest.h>
#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "common/common.h"
#include "sitlnet/medium.pb.h"
#include "tests/integration/test_util.h"

namespace sitlnet::tapbridge::testing {

// The shared helpers (test_util.h).
using integration_test::Child;
using integration_test::CommandResult;
using integration_test::IsCi;
using integration_test::PingProgram;
using integration_test::RunCommand;
using integration_test::SitlnetBinary;
using integration_test::SourceDir;

// Why the tests cannot run here (not root), or empty.
std::string MissingRoot();

#define SITLNET_REQUIRE_ROOT()                                                \
  do {                                                                        \
    const std::string missing = ::sitlnet::tapbridge::testing::MissingRoot(); \
    if (!missing.empty()) {                                                   \
      if (::sitlnet::tapbridge::testing::IsCi()) FAIL() << missing;           \
      GTEST_SKIP() << missing;                                                \
    }                                                                         \
  } while (0)

// A scenario `sitlnet up` under a unique name (tag, pid, slot) with unique
// subnets; `body` holds robot/radio/obstacle lines (no name, no addresses).
// The destructor stops the daemon (SIGTERM, then SIGKILL) and runs
// `sitlnet down NAME`.
class MediumScenario {
 public:
  // `address_extra` goes inside the `addresses { }` block (e.g. "ipv6: IPV6_LINK_LOCAL").
  MediumScenario(const std::string& tag, int slot, const std::string& body,
                 const std::string& address_extra = "");
  ~MediumScenario();
  const std::string& name() const { return name_; }
  const std::string& path() const { return path_; }
  const std::string& dir() const { return dir_; }
  // wlan0 address of robot `index` (host index+1 of the wlan subnet).
  std::string Address(int index) const;
  std::string Netns(const std::string& robot) const { return name_ + "-" + robot; }

  // Starts `sitlnet medium` with `args`; waits for its "attached" line.
  void StartDaemon(const std::vector<std::string>& args = {});
  // SIGTERM and wait; returns the daemon's stderr.
  std::string StopDaemon();
  Child* daemon() { return daemon_.get(); }

  // Runs argv inside robot `robot` (by name) with `sitlnet exec`.
  CommandResult Exec(const std::string& robot, const std::vector<std::string>& argv,
                     TimeNs timeout_ns = 60 * kNsPerS);
  std::unique_ptr<Child> Spawn(const std::string& robot, const std::vector<std::string>& argv);

  proto::MediumStatus Counters();
  void SetPosition(const std::string& robot, double x, double y, double z);

 private:
  std::string name_, path_, dir_, subnet_prefix_;
  bool up_ = false;
  std::unique_ptr<Child> daemon_;
};

//------------------------- 802.11 timing (the oracle) ------------------------
// IEEE 802.11-2016 clause 17 (OFDM): TXTIME = 20 µs preamble+SIGNAL +
// 4 µs x ceil((16 service + 8 L + 6 tail) / N_DBPS), N_DBPS = 4 x rate.
TimeNs OfdmAirtimeNs(int psdu_bytes, double rate_mbps);
// Control response rate: highest 11a basic rate (6, 12, 24) <= data rate.
double OfdmAckRateMbps(double rate_mbps);
inline constexpr TimeNs kOfdmSlotNs = 9000, kOfdmSifsNs = 16000, kOfdmDifsNs = 34000;
inline constexpr int kOfdmCwMin = 15;
// An Ethernet frame of E bytes is E + 22 on air: 24 MAC header + 8 LLC/SNAP +
// 4 FCS - 14 Ethernet header.
inline constexpr int kEthernetToPsduBytes = 22;
inline constexpr int kAckBytes = 14;

// Bianchi-style one-station saturation goodput (no collisions): payload bits
// per DIFS + mean backoff (CWmin/2 slots) + DATA + SIFS + ACK.
double OneStationGoodputMbps(int udp_payload_bytes, double rate_mbps);

}  // namespace sitlnet::tapbridge::testing

#endif  // SITLNET_TESTS_INTEGRATION_TAPBRIDGE_TEST_UTIL_H_
