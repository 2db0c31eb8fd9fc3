// Helpers shared by every integration suite: child processes with captured output and bounded
// waits, the privilege rules (CI=true, the min-caps pass), paths of the tree under test, and a
// ping that runs without CAP_NET_RAW. Suite-specific helpers (nns_test_util.h,
// tapbridge_test_util.h) build on these.
#ifndef SITLNET_TESTS_INTEGRATION_TEST_UTIL_H_
#define SITLNET_TESTS_INTEGRATION_TEST_UTIL_H_

#include <gtest/gtest.h>
#include <sys/types.h>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "common/common.h"

namespace sitlnet::integration_test {

//------------------------------- Privileges ---------------------------------

// CI=true: a missing privilege fails the test instead of skipping it.
bool IsCi();

// SITLNET_MIN_CAPS=1, set by run_with_min_caps.sh: the suite runs holding only CAP_NET_ADMIN +
// CAP_SYS_ADMIN on purpose, so a check that needs another capability skips (naming it) even
// under CI=true.
bool IsMinCapsPass();

// Whether capability `cap` (CAP_NET_RAW, ...) is in this process's effective set.
bool HasCapability(int cap);

// Skips the test when capability `cap` is missing: always in the min-caps pass, which lacks it
// on purpose; otherwise fails under CI=true and skips elsewhere. `why` says what needs it.
#define SITLNET_REQUIRE_CAPABILITY(cap, why)                                                      \
  do {                                                                                            \
    if (!::sitlnet::integration_test::HasCapability(cap)) {                                       \
      if (::sitlnet::integration_test::IsCi() && !::sitlnet::integration_test::IsMinCapsPass()) { \
        FAIL() << "needs " #cap " (" << (why) << ")";                                             \
      }                                                                                           \
      GTEST_SKIP() << "needs " #cap " (" << (why) << "), not held in this run";                   \
    }                                                                                             \
  } while (0)

// What scripts/setup says of one of its optional groups of packages ("containers",
// "browser"): `scripts/setup --check GROUP`, so the tests and the script agree on what this
// machine should have.
struct SetupVerdict {
  bool for_this_machine = true;  // false: this machine cannot use it (the line says why).
  std::string line;              // scripts/setup's line: what is missing and how to install it.
};
SetupVerdict AskSetup(const std::string& group);

// Skips or fails when `why_missing` (a tool of scripts/setup's group `group`) is not empty: a
// skip naming the capability when scripts/setup says the group is not for this machine, even
// under CI=true; otherwise a failure under CI=true (scripts/setup should have installed it) and
// a skip elsewhere, each with scripts/setup's line.
#define SITLNET_REQUIRE_SETUP_GROUP(group, why_missing)                                   \
  do {                                                                                    \
    if (const std::string missing = (why_missing); !missing.empty()) {                    \
      const ::sitlnet::integration_test::SetupVerdict verdict =                           \
          ::sitlnet::integration_test::AskSetup(group);                                   \
      if (verdict.for_this_machine && ::sitlnet::integration_test::IsCi()) {              \
        FAIL() << missing << "; " << verdict.line;                                        \
      }                                                                                   \
      GTEST_SKIP() << missing << "; " << verdict.line;                                    \
    }                                                                                     \
  } while (0)

//-------------------------------- Processes ---------------------------------

struct CommandResult {
  int exit_code = -1;  // 128+signal if killed, as a shell reports it.
  std::string out;
  std::string err;
};

// A running child (execvp of argv, stdin /dev/null) with pipes on stdout and stderr; killed
// (SIGKILL, by pid) and reaped on destruction if still running. `env` entries "K=V" are added
// to the environment.
class Child {
 public:
  // `before_exec`, if given, runs in the child between fork and exec (async-signal-safe calls
  // only); it may call _exit.
  explicit Child(const std::vector<std::string>& argv, const std::vector<std::string>& env = {},
                 const std::function<void()>& before_exec = nullptr);
  ~Child();
  Child(const Child&) = delete;
  Child& operator=(const Child&) = delete;

  pid_t pid() const { return pid_; }
  // Reads stdout or stderr until `needle` appears, the stream ends or the deadline passes.
  bool WaitForOutput(bool from_stderr, const std::string& needle, TimeNs timeout_ns);
  // Waits for exit up to timeout_ns (0: just a look); returns the exit code (128+signal), or
  // -1 on timeout, after which the child is killed and reaped.
  int Wait(TimeNs timeout_ns);
  // Exit code if it has exited (reaped now), else -1; never kills.
  int Poll();
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

// Waits (inotify on the folder, no sleeps) until `done()` holds or the timeout passes.
bool WaitForFiles(const std::string& dir, const std::function<bool()>& done, TimeNs timeout_ns);

// Runs argv to completion (killed after timeout_ns), capturing its output.
CommandResult RunCommand(const std::vector<std::string>& argv, TimeNs timeout_ns = 30 * kNsPerS,
                         const std::vector<std::string>& env = {});

// Runs argv to completion as this user but without the capabilities in `drop_mask` (bit i =
// capability i, ~0 for all): the child sets no_new_privs, then clears them from its effective,
// permitted and inheritable sets. no_new_privs keeps an exec as uid 0 from granting them back
// (security/commoncap.c, cap_bprm_creds_from_file), so unlike dropping them from the bounding
// set (setpriv) this needs no CAP_SETPCAP and works in the min-caps pass. Exit code 126 if the
// child could not drop them.
CommandResult RunWithoutCapabilities(const std::vector<std::string>& argv, uint64_t drop_mask,
                                     TimeNs timeout_ns = 30 * kNsPerS);

//---------------------------------- Paths -----------------------------------

// The whole file (binary-safe); empty if it cannot be read.
std::string ReadAll(const std::string& path);
// A folder private to this test process under $TMPDIR (or /tmp), removed at normal exit.
std::string TempDir();
// The host's CPUs over an interval, from /proc/stat: the share of their time busy (user, system,
// interrupts: this process's children included) and the share a hypervisor took (stolen).
class HostCpuWatch {
 public:
  HostCpuWatch();  // The interval starts now.
  struct Shares {
    double busy = 0;    // 0..1
    double stolen = 0;  // 0..1
  };
  Shares SharesUpToNow() const;  // One read of /proc/stat.

 private:
  unsigned long long busy_ = 0, idle_ = 0, stolen_ = 0;  // jiffies of all CPUs at the start
};

// "host load average X, Y, Z on N cores" (/proc/loadavg) and the CPUs' busy and stolen shares
// since `since` began (by default since the test process began): printed with a realtime
// flight's failure, where an autopilot short of CPU misses its own clock (docs/autopilots.md).
std::string HostLoad(const HostCpuWatch* since = nullptr);
// `text` without its lines that start with one of `prefixes`, and a last line saying how many
// were left out: a flight's failure prints the ground station's events, not its position reports.
std::string WithoutLines(const std::string& text, const std::vector<std::string>& prefixes);
// <build>/bin/sitlnet of the tree under test ($SITLNET_BINARY_DIR, else from /proc/self/exe).
std::string SitlnetBinary();
// $SITLNET_SOURCE_DIR, else ".".
std::string SourceDir();
// `value` in base 36 (digits, then a-z): short unique names from a pid (interface names have
// at most 15 characters).
std::string Base36(unsigned value);

//----------------------------------- ping -----------------------------------

// The ping(8) to run inside a robot. Debian's /usr/bin/ping carries the file capability
// cap_net_raw=ep, and the kernel refuses to exec a file whose file capabilities are not all in
// the bounding set (EPERM): without CAP_NET_RAW in the bounding set (the min-caps pass, a
// container without NET_RAW) this returns a copy without file capabilities, made once per
// process under TempDir() and removed at exit. That copy opens ICMP datagram sockets, which
// `sitlnet up` allows in every robot namespace (net.ipv4.ping_group_range, docs/nns.md).
std::string PingProgram();
// That copy without file capabilities, whatever this process holds: as an unprivileged user it
// can only use ICMP datagram sockets.
std::string PingWithoutFileCapabilities();

}  // namespace sitlnet::integration_test

#endif  // SITLNET_TESTS_INTEGRATION_TEST_UTIL_H_
