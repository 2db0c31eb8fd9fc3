// Helpers for the nns integration tests: privilege gate, unique scenarios,
// cleanup guards, and running programs (the CLI, `ip`, tcpdump) with bounded
// waits. `ip` is used only as an independent observer, never by the library.
#ifndef SITLNET_TESTS_INTEGRATION_NNS_TEST_UTIL_H_
#define SITLNET_TESTS_INTEGRATION_NNS_TEST_UTIL_H_

#include <gtest/gtest.h>
#include <sys/types.h>

#include <string>
#include <vector>

#include "nns/nns.h"
#include "scenario/scenario.h"

namespace sitlnet::nns::testing {

bool IsCi();

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

struct CommandResult {
  int exit_code = -1;  // 128+signal if killed, as a shell reports it.
  std::string out;
  std::string err;
};

// Runs argv to completion (killed after timeout_ns), capturing its output.
// `env` entries "K=V" are added to the environment.
CommandResult RunCommand(const std::vector<std::string>& argv, TimeNs timeout_ns = 30 * kNsPerS,
                         const std::vector<std::string>& env = {});

// A running child with pipes on stdout and stderr; killed (SIGKILL) and
// reaped on destruction if still running.
class Child {
 public:
  Child(const std::vector<std::string>& argv, const std::vector<std::string>& env = {});
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  // Reads stdout or stderr until `needle` appears or the deadline passes.
  bool WaitForOutput(bool from_stderr, const std::string& needle, TimeNs timeout_ns);
  // Waits for exit up to timeout_ns; returns exit code (128+signal) or -1.
  int Wait(TimeNs timeout_ns);
  const std::string& out() const { return out_; }
  const std::string& err() const { return err_; }

 private:
  // One poll round on the pipes (and the pidfd); reads what is there.
  void Drain(TimeNs timeout_ns, bool wake_on_exit);
  pid_t pid_ = -1;
  int pidfd_ = -1;
  int out_fd_ = -1;
  int err_fd_ = -1;
  int status_ = -1;
  std::string out_;
  std::string err_;
};

// Effective capability `cap` (CAP_NET_RAW, ...) of this process. The suite
// must pass with only CAP_NET_ADMIN + CAP_SYS_ADMIN (issue 2, item 6): the
// observers that need more (ping and tcpdump need CAP_NET_RAW, setpriv needs
// CAP_SETPCAP to drop capabilities) run only when it is there.
bool HasCapability(int cap);

// Sends a UDP datagram from the root namespace to `robot_address` and waits
// for the echo sent back by a socket bound inside namespace `netns` (by a
// test thread that entered it with setns). No capability beyond setns.
// Returns an empty string on success, else what went wrong.
std::string UdpRoundTrip(const std::string& netns, Ipv4 robot_address);

// The whole file (binary-safe); empty if it cannot be read.
std::string ReadAll(const std::string& path);
// $TMPDIR, or /tmp.
std::string TempDir();

// build/bin/sitlnet of the tree under test.
std::string SitlnetBinary();

bool LinkExistsInRoot(const std::string& name);
bool StateExists(const std::string& scenario);

}  // namespace sitlnet::nns::testing

#endif  // SITLNET_TESTS_INTEGRATION_NNS_TEST_UTIL_H_
