// Helpers for the nns integration tests: privilege gate, unique scenarios, cleanup guards, a UDP
// round trip into a robot; programs (the CLI, `ip`, tcpdump) run through test_util.h. `ip` is
// used only as an independent observer, never by the library.
#ifndef SITLNET_TESTS_INTEGRATION_NNS_TEST_UTIL_H_
#define SITLNET_TESTS_INTEGRATION_NNS_TEST_UTIL_H_

#include <gtest/gtest.h>
#include <sys/types.h>

#include <string>
#include <vector>

#include "nns/nns.h"
#include "scenario/scenario.h"
#include "tests/integration/test_util.h"

namespace sitlnet::nns::testing {

// The shared helpers (test_util.h), under the names these tests have always used.
using integration_test::Child;
using integration_test::CommandResult;
using integration_test::HasCapability;
using integration_test::IsCi;
using integration_test::PingProgram;
using integration_test::ReadAll;
using integration_test::RunCommand;
using integration_test::RunWithoutCapabilities;
using integration_test::SitlnetBinary;
using integration_test::TempDir;
using integration_test::WaitForFiles;

// Skips the test (fails under CI=true) when namespaces cannot be created.
#define SITLNET_REQUIRE_NNS_PRIVILEGES()                                         \
  do {                                                                           \
    if (auto missing = ::sitlnet::nns::MissingPrivileges()) {                    \
      if (::sitlnet::nns::testing::IsCi()) FAIL() << *missing;                   \
      GTEST_SKIP() << "needs root or CAP_NET_ADMIN+CAP_SYS_ADMIN: " << *missing; \
    }                                                                            \
  } while (0)

// A scenario whose name and subnets are unique to this process and `slot`
// (0..9), so that parallel test runs and other users' scenarios do not clash.
// `addresses_text` goes inside the addresses block, `extra_text` at the end. Written to a file
// under $TMPDIR (or /tmp).
struct TestScenario {
  std::string path;
  Scenario scenario;
};
TestScenario MakeScenario(const std::string& tag, int slot, int robots,
                          const std::string& addresses_text = "",
                          const std::string& extra_text = "");

// Runs Down(name) on destruction, whatever happened.
class DownGuard {
 public:
  explicit DownGuard(std::string name) : name_(std::move(name)) {}
  ~DownGuard();
  DownGuard(const DownGuard&) = delete;
  DownGuard& operator=(const DownGuard&) = delete;

 private:
  std::string name_;
};

// Runs `command` (a shell-free argv) on destruction, for foreign objects the
// test creates itself ("ip netns del X", "ip link del Y").
class CommandGuard {
 public:
  explicit CommandGuard(std::vector<std::string> command) : command_(std::move(command)) {}
  ~CommandGuard();

 private:
  std::vector<std::string> command_;
};

// Sends a UDP datagram from `scenario`'s ctl namespace (the root side of every ctl0) to
// `robot_address` and waits for the echo sent back by a socket bound inside namespace `netns`
// (by a test thread that entered it with setns). No capability beyond setns.
// Returns an empty string on success, else what went wrong.
std::string UdpRoundTrip(const std::string& scenario, const std::string& netns, Ipv4 robot_address);

bool LinkExistsInRoot(const std::string& name);
// True if link `name` exists in the scenario's ctl namespace (false if there is none).
bool LinkExistsInCtl(const std::string& scenario, const std::string& name);
bool StateExists(const std::string& scenario);

// Writes an image manifest `name: "<name>"` + `body` (text format) into this process's TempDir()
// and returns its path, for a scenario's `image:`.
std::string WriteImageManifest(const std::string& name, const std::string& body);

}  // namespace sitlnet::nns::testing

#endif  // SITLNET_TESTS_INTEGRATION_NNS_TEST_UTIL_H_
