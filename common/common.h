// sitlnet common: errors, time units and small network value types shared by
// every module. One public header per module; this is the one for common/.
#ifndef SITLNET_COMMON_COMMON_H_
#define SITLNET_COMMON_COMMON_H_

#include <signal.h>

#include <array>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace sitlnet {

//---------------------------------- Errors ----------------------------------

// Bad input or a failed system operation. what() is one line that names the
// place (file:line:col, robot, device) and the rule or the system error.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Always-on invariant check for bugs (not for bad input): prints the condition
// and aborts, as Drake's DRAKE_DEMAND does.
[[noreturn]] void DemandFailed(const char* condition, const char* file, int line);
#define SITLNET_DEMAND(condition)                              \
  do {                                                         \
    if (!(condition)) {                                        \
      ::sitlnet::DemandFailed(#condition, __FILE__, __LINE__); \
    }                                                          \
  } while (0)

// "<what>: <strerror(err)>", iproute2 style.
std::string SystemErrorMessage(std::string_view what, int err);

// True if `owner` is the user this process works for: its effective user, or under sudo (root,
// SUDO_UID set) the user who ran sudo. Files of that user are the user's own to trust.
bool IsInvokingUser(unsigned owner);

//----------------------------------- Time -----------------------------------

// Virtual and wall time are integer nanoseconds everywhere.
// A point or vector in 3-D (metres, m/s, ...: the unit is in the name of the variable). The
// one geometric type of the data path: physics positions, medium station positions, obstacles.
struct Vec3d {
  double x = 0, y = 0, z = 0;
};

using TimeNs = int64_t;
inline constexpr TimeNs kNsPerUs = 1000;
inline constexpr TimeNs kNsPerMs = 1000 * kNsPerUs;
inline constexpr TimeNs kNsPerS = 1000 * kNsPerMs;

// CLOCK_MONOTONIC in nanoseconds.
TimeNs MonotonicNowNs();

//-------------------------------- Privileges --------------------------------

// Whether the calling thread holds capability `cap` (CAP_* from <linux/capability.h>) in its
// effective set, read with capget (no libcap dependency).
bool HasEffectiveCapability(int cap);

//-------------------------------- Scheduling --------------------------------

// Asks for SCHED_FIFO `priority` (1..99) for the calling thread; threads it creates afterwards
// inherit it. Realtime loops (the medium daemon, `sitlnet run` in realtime pacing) use it because
// on a busy 2-core host a normal-priority loop waits milliseconds for a core
// (docs/performance.md). Returns "" on success, else a one-line reason (no CAP_SYS_NICE,
// RLIMIT_RTPRIO) for the caller to print as a warning: running at normal priority still works.
std::string RequestRealtimePriority(int priority);

// The SCHED_FIFO priority sitlnet's realtime loops ask for unless told (`--rt-priority`). Above
// PX4's MAVLink threads (50) and navigator (55), which kept 8 realtime PX4's iteration lag p99 at
// 2.4-2.8 ms under priority 10; below its logger (74), commander (90) and work queues (99), so
// sitlnet never delays PX4's control loop (docs/performance.md, "Realtime: the iteration lag").
inline constexpr int kDefaultRealtimePriority = 60;

// Does nothing if the thread already has a realtime policy (a run started under `chrt -f`: the
// caller's choice stands).
//
// In a forked child before exec: back to SCHED_OTHER if RequestRealtimePriority raised this
// process, so that programs started by the harness (robot images, gnuplot) do not inherit a
// priority they were not given; a policy inherited from the caller is passed on unchanged.
// Lowering needs no privilege.
void ResetToNormalScheduling();

//------------------------------ Resource limits -----------------------------

// Raises the soft open-file limit (RLIMIT_NOFILE) to at least `needed`, and the hard limit too
// when that is below (needs CAP_SYS_RESOURCE). Debian's default soft limit, 1024, is near what
// 250 robots take. Returns the soft limit now in force; throws Error "<what> needs N open
// files, above the hard limit of H ..." when it cannot be raised far enough.
uint64_t RaiseOpenFileLimit(uint64_t needed, std::string_view what);

//-------------------------------- Programs ----------------------------------

// Runs `argv` (argv[0] a path or a name on $PATH) to its end with stdin, stdout and stderr on
// /dev/null, at normal scheduling priority; its exit status (128+N for signal N), or -1 when it
// could not be started.
int RunProgramQuietly(const std::vector<std::string>& argv);

// Runs gnuplot in `dir` on `script`, fed through a pipe (its messages go to `log_path`); empty
// string on success, else the reason. No file is read and no path is written into the script: a
// folder named with a quote cannot inject gnuplot commands (such as system()), and nothing in the
// folder can be swapped in between writing and reading (issue 17, finding 7). A caller that puts
// its own text in the script quotes it with GnuplotQuoted.
std::string RunGnuplot(const std::string& script, const std::string& dir,
                       const std::string& log_path);

// `text` as one gnuplot single-quoted string: its quotes doubled, newlines refused (Error).
std::string GnuplotQuoted(const std::string& text);

//--------------------------------- Files ------------------------------------

// Owns one file descriptor; closes it on destruction. -1 means empty. Every module's fds.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) : fd_(fd) {}
  UniqueFd(UniqueFd&& other) noexcept : fd_(other.Release()) {}
  UniqueFd& operator=(UniqueFd&& other) noexcept;
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { Reset(); }

  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  int Release();
  void Reset(int fd = -1);

 private:
  int fd_ = -1;
};

// SIGINT/SIGTERM -> an orderly stop, the one way every sitlnet process takes them. The handler
// only writes a byte to a pipe (async-signal-safe); a process's waits poll the read end, so a
// signal ends a wait at once instead of after a timeout (common/stop_signal.cc).
class StopSignal {
 public:
  // Installs handlers for SIGINT and SIGTERM; one instance at a time.
  StopSignal();
  // Restores the previous handlers.
  ~StopSignal();
  StopSignal(const StopSignal&) = delete;
  StopSignal& operator=(const StopSignal&) = delete;

  // Readable once a signal arrived (or Request() was called).
  int fd() const { return read_fd_; }
  bool requested() const;
  // Blocks until a signal arrived (or Request() was called); at once if one did already.
  void Wait() const;
  // The signal that arrived (0 if Request() or none).
  int signal_number() const;
  // Same effect as a signal (tests, a CLI "stop" command, another thread).
  void Request();

 private:
  int read_fd_ = -1;
  int write_fd_ = -1;
  struct sigaction previous_int_ {};
  struct sigaction previous_term_ {};
};

// SIGINT and SIGTERM blocked in the calling thread for a scope, so that threads started there
// (a server's) never take them: they are for the thread that waits on the StopSignal.
class StopSignalsBlocked {
 public:
  StopSignalsBlocked();
  ~StopSignalsBlocked();
  StopSignalsBlocked(const StopSignalsBlocked&) = delete;
  StopSignalsBlocked& operator=(const StopSignalsBlocked&) = delete;

 private:
  sigset_t previous_{};
};

// A file of a run (CSV, logs, the pcap) appended as whole lines or records: buffered, written
// with one write(2) per flush (every `lines_per_flush` lines or records and at destruction), so
// an interrupted run leaves only complete ones. Opened close-on-exec (robot processes started
// later never inherit it) and without following a symbolic link at `path`. Not thread-safe.
class LineFile {
 public:
  // Creates/truncates `path` and writes `header` (a line, without newline;
  // empty: none). Errors name `what` and the path: 'create <what> "<path>": ...'.
  LineFile(const std::string& path, const std::string& header, int lines_per_flush = 256,
           std::string_view what = "file");
  ~LineFile();  // Flushes; a write error is printed, not thrown.
  LineFile(const LineFile&) = delete;
  LineFile& operator=(const LineFile&) = delete;
  void Append(std::string_view line);         // Without the newline.
  void AppendRecord(std::string_view bytes);  // Binary, written as is.
  // Throws Error naming the file if write(2) fails (disk full); the lines
  // written before stay whole.
  void Flush();

 private:
  std::string path_;
  std::string what_;
  int fd_ = -1;
  int lines_per_flush_;
  int pending_ = 0;
  std::string buffer_;
};

// The SHA-256 of the file at `path`: 64 lowercase hex digits, read in 1 MiB blocks through
// OpenSSL's EVP interface (libcrypto; the run record of summary.json, `sitlnet verify`). Throws
// Error naming the file if it cannot be opened or read.
std::string Sha256HexOfFile(const std::string& path);

//--------------------------------- Version ----------------------------------

// sitlnet's version: the git commit its build was configured from (`git rev-parse HEAD` when
// cmake ran), or "unknown" when the sources were not a git checkout.
std::string_view SitlnetVersion();

//---------------------------- Network value types ---------------------------

// An IPv4 address in host byte order.
struct Ipv4 {
  uint32_t host_order = 0;
  friend bool operator==(Ipv4, Ipv4) = default;
  friend auto operator<=>(Ipv4, Ipv4) = default;
};

// Parses a dotted quad; nullopt if malformed.
std::optional<Ipv4> ParseIpv4(std::string_view text);
std::string FormatIpv4(Ipv4 address);

// An IPv4 prefix, e.g. 10.77.0.0/24. The address is normalized to the network.
struct Ipv4Prefix {
  Ipv4 network;
  int length = 0;
  uint32_t Mask() const { return length == 0 ? 0 : ~uint32_t{0} << (32 - length); }
  bool Contains(Ipv4 address) const { return (address.host_order & Mask()) == network.host_order; }
  bool Overlaps(const Ipv4Prefix& other) const;
  Ipv4 Broadcast() const { return Ipv4{network.host_order | ~Mask()}; }
  // Number of addresses in the prefix (2^(32-length)).
  uint64_t Size() const { return uint64_t{1} << (32 - length); }
};

// Parses "a.b.c.d/len"; nullopt if malformed or if host bits are set.
std::optional<Ipv4Prefix> ParseIpv4Prefix(std::string_view text);
std::string FormatIpv4Prefix(const Ipv4Prefix& prefix);

// A 48-bit Ethernet/802.11 MAC address.
struct MacAddress {
  std::array<uint8_t, 6> bytes{};
  friend bool operator==(const MacAddress&, const MacAddress&) = default;
  bool IsGroup() const { return (bytes[0] & 0x01) != 0; }  // broadcast/multicast
};
std::string FormatMac(const MacAddress& mac);
// The locally administered MAC of robot `index`: 02:00:00:00:hi:lo.
MacAddress RobotMac(int index);

}  // namespace sitlnet

#endif  // SITLNET_COMMON_COMMON_H_
