// sitlnet run_formats: the files of a run folder (docs/run.md) and what is computed for them as
// the run goes, written by the runner and read by the view (live and replayed). No process, no
// system but files.
#ifndef SITLNET_RUN_FORMATS_RUN_FORMATS_H_
#define SITLNET_RUN_FORMATS_RUN_FORMATS_H_

#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "common/common.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "scenario/scenario.h"

namespace sitlnet::run_formats {

//------------------ Timing per simulated second (metrics.csv; second_timing.cc) -------------------
// The iterations' timing per simulated second (metrics.csv's stf and lag_ns): what the view's
// timeline draws, live and replayed, from the same arithmetic.

// The iterations that start in second `second` (start_ns / 1 s).
struct SecondTiming {
  int64_t second = 0;
  int64_t iterations = 0;
  double stf_mean = 0, stf_max = 0;
  TimeNs lag_max_ns = 0;
};

// Sums iterations, in start order, into seconds. A few additions per iteration, no allocation.
class SecondTimingAccumulator {
 public:
  // Adds one iteration. Returns the previous second once this iteration starts a later one.
  std::optional<SecondTiming> Add(TimeNs start_ns, double stf, TimeNs lag_ns);
  // The last second, if it has an iteration; then starts afresh.
  std::optional<SecondTiming> Finish();

 private:
  SecondTiming current_;
  double stf_sum_ = 0;
};

//----------------------------------------- The live sink ------------------------------------------
// What `sitlnet run --view` is told while the run goes (view/live_feed.h): the robots' poses at
// every trajectories.csv sample, each second's links as links.csv will count them, each
// connectivity.csv sample, each second's iteration timing, and what the GCS relay heard. Called
// on the run's own threads (physics, coordinator), at most every 100 ms of simulated time each:
// an implementation must never block or wait. One exception, bounded: the GCS relay's counts are
// copied at most every 200 ms of wall time under the relay's lock, which its thread holds for
// one wake-up's work (runner/gcs_relay_stage.cc).

struct LivePose {
  double x_m = 0, y_m = 0, z_m = 0;
  double speed_m_s = 0;
};

// One links.csv row: DATA frames from `from` at station `to` in a second (to -1: sender drops
// of group frames), those decoded, and the most frequent loss.
struct LinkRow {
  int64_t second = 0;
  int from = 0, to = 0;
  uint64_t frames = 0, delivered = 0;
  const char* main_cause = "none";
  uint64_t main_cause_frames = 0;
  // The PHY rate and, for HT/VHT, the MCS (else -1) of the link's last DATA frame in the second.
  double rate_mbps = 0;
  int mcs = -1;
};

// What the GCS relay heard of one vehicle (a MAVLink system id) so far: gcs::VehicleCounters,
// with the robot whose radio address sent it.
struct LiveVehicle {
  int robot = -1;  // Robot index; -1: no robot of the scenario has the sender's address.
  uint8_t system_id = 0;
  uint64_t messages = 0;
  uint64_t sequence_gaps = 0;   // Frames missing by sequence numbers: MAVLink loss over the radio.
  bool heartbeat_seen = false;  // An autopilot's HEARTBEAT; the fields below are its latest.
  uint8_t type = 0, autopilot = 0, base_mode = 0;  // MAV_TYPE, MAV_AUTOPILOT, MAV_MODE_FLAG
  uint32_t custom_mode = 0;
  bool armed = false;
};

class LiveSink {
 public:
  virtual ~LiveSink() = default;
  // Physics thread: every robot's pose (by index) at `time_ns`, as trajectories.csv samples it.
  virtual void Poses(TimeNs time_ns, const std::vector<LivePose>& poses) = 0;
  // Coordinator thread: the rows of a second no transmission can still add to.
  virtual void Links(int64_t second, const std::vector<LinkRow>& rows) = 0;
  // Coordinator thread: connectivity.csv's row at `time_ns` (every 100 ms of simulated time,
  // once a later delivery or the run's end shows it): the count of components and, per robot,
  // its component's smallest robot index.
  virtual void Components(TimeNs time_ns, int components, const std::vector<int>& component_of) = 0;
  // Coordinator thread: a simulated second's iterations (metrics.csv), once the next began.
  virtual void Timing(const SecondTiming& second) = 0;
  // Coordinator thread, a few times a second of wall time in a run with a GCS relay: every
  // vehicle the relay heard, by system id, at simulated time `time_ns`.
  virtual void Vehicles(TimeNs /*time_ns*/, const std::vector<LiveVehicle>& /*vehicles*/) {}
};

//----------------------------- Closest approach (closest_approach.cc) -----------------------------
// The closest two robots came during a run (summary.json "separation"): the smallest distance
// between any two robots' positions at the instants trajectories.csv samples. A swept
// experiment's collision margin (docs/sweep-reference.md, "Metrics").

struct ClosestApproach {
  double distance_m = 0;  // 3D, between the robots' body origins.
  TimeNs time_ns = 0;     // The first sample at which it was reached.
  int robot_a = 0;        // Global robot indices, robot_a < robot_b.
  int robot_b = 0;
};

class ClosestApproachTracker {
 public:
  // `positions_m`: x, y, z of every robot of the run, in global index order, at `time_ns`.
  // Samples come in time order; a tie keeps the earlier sample and then the lower pair.
  void Sample(TimeNs time_ns, const std::vector<double>& positions_m);
  // Null before a sample with two robots or more.
  const std::optional<ClosestApproach>& closest() const { return closest_; }

 private:
  std::optional<ClosestApproach> closest_;
  double closest_m2_ = 0;  // Its squared distance, compared as found (no rounding through sqrt).
};

//--------------------------------- Connectivity (connectivity.cc) ---------------------------------
// Communication graph over time, from the medium's deliveries: robots i and j are linked at time
// t when either received a frame from the other within the window (t - window, t]. The graph's
// connected components show when a fleet splits and reunites (DANCERS paper, Fig. 6).

struct ConnectivitySample {
  TimeNs time_ns = 0;
  int components = 0;
  std::vector<int> component_of;  // Per robot: its component's smallest robot index.
};

// Samples the graph every `sample_period_ns` (at sample_period_ns, 2 * sample_period_ns, ...)
// while deliveries stream in, so a run keeps no log of them in memory.
class ConnectivityTracker {
 public:
  ConnectivityTracker(int robots, TimeNs window_ns, TimeNs sample_period_ns);

  // A frame from robot `from` reached robot `to` at virtual time `time_ns`. Deliveries come in
  // time order (the medium's); a delivery at a sample's instant counts for that sample. Robots
  // out of range and self-deliveries are ignored.
  void Heard(TimeNs time_ns, int from, int to);

  // `sink` (may be null; outlives this) is told each sample as it is taken.
  void SetLiveSink(LiveSink* sink) { live_ = sink; }

  // Takes every sample up to `end_ns` (inclusive) and returns them all.
  std::vector<ConnectivitySample> Finish(TimeNs end_ns);

 private:
  void SampleUntilBefore(TimeNs time_ns);  // Takes the samples at instants < time_ns.
  int robots_;
  TimeNs window_ns_;
  TimeNs sample_period_ns_;
  TimeNs next_sample_ns_;
  std::vector<TimeNs> last_heard_;  // [a * robots + b], a < b: latest delivery either way.
  std::vector<ConnectivitySample> samples_;
  LiveSink* live_ = nullptr;
};

//------------------------- The run folder's files and plots (outputs.cc) --------------------------
// The files of a run folder (docs/run.md): trajectories.csv, deliveries.csv,
// connectivity.csv, summary.json, and the PNG plots drawn by gnuplot.

// One robot's pose sample for trajectories.csv.
struct PoseRow {
  TimeNs time_ns = 0;
  int robot = 0;
  double x_m = 0, y_m = 0, z_m = 0;
  double qw = 1, qx = 0, qy = 0, qz = 0;
  double vx_m_s = 0, vy_m_s = 0, vz_m_s = 0;
  // The position on Earth (the scenario's geodetic_origin): WGS-84, altitude above sea level.
  double latitude_deg = 0, longitude_deg = 0, altitude_m = 0;
};
inline constexpr char kTrajectoryHeader[] =
    "time_s,robot,x_m,y_m,z_m,qw,qx,qy,qz,vx_m_s,vy_m_s,vz_m_s,latitude_deg,longitude_deg,"
    "altitude_m";
std::string FormatPoseRow(const PoseRow& row);

inline constexpr char kDeliveryHeader[] = "time_ns,from,to,rx_power_dbm,sinr_db";

// Writes connectivity.csv: time_s,components,robot_0,...,robot_{n-1} (each
// robot's component id).
void WriteConnectivityCsv(const std::string& path, const std::vector<ConnectivitySample>& samples,
                          int robots);

// Draws trajectories.png (top view over the obstacles), connectivity.png and
// stf.png into `run_dir` with gnuplot. Returns the PNGs written; a missing
// gnuplot or a failed plot is a warning line in *warnings, not an error.
std::vector<std::string> DrawPlots(const std::string& run_dir, const Scenario& scenario,
                                   const std::string& title, std::vector<std::string>* warnings);

//-------------------------------------- Losses (loss_log.cc) --------------------------------------
// losses.csv.gz and links.csv of a run folder (docs/run.md): what happened to
// every frame at every station it reached above the noise floor, and every
// frame its sender dropped, as the 802.11 model decided it (mac_phy_sim's
// trace with EnableCauses); and per second and link, the delivery ratio and
// the main cause of loss.

inline constexpr char kLossHeader[] =
    "time_ns,from,to,kind,seq,retry,station,cause,interferer,rx_power_dbm,sinr_db,path_loss_db,"
    "obstacle_loss_db";
inline constexpr char kLinkHeader[] =
    "second,from,to,frames,delivered,delivery_ratio,main_cause,main_cause_frames,rate_mbps,mcs";

// The word losses.csv.gz and links.csv use for a cause.
const char* CauseName(mac::RxCause cause);
const char* DropName(mac::DropReason reason);

// DATA transmissions at the station they are for (every station for a group frame), as
// links.csv counts them, split by link class (summary.json "delivery").
struct DeliveryCounts {
  uint64_t frames = 0;
  uint64_t delivered = 0;
};
struct DeliveryByLinkClass {
  DeliveryCounts line_of_sight;  // No box crosses the segment from sender to receiver.
  DeliveryCounts obstructed;     // A box does (mac::RxRecord::obstructed).
};

class LossLog {
 public:
  // Creates run_dir/losses.csv.gz (zlib, gzip format) and, at Finish,
  // run_dir/links.csv. `stations`: each station's MAC (the robot index is its
  // position); receptions under `noise_floor_dbm` are left out. A reception
  // under the preamble threshold `detect_min_rssi_dbm` counts in links.csv as
  // due to obstacles if it would have reached it without their loss.
  LossLog(const std::string& run_dir, std::vector<MacAddress> stations, double noise_floor_dbm,
          double detect_min_rssi_dbm);
  ~LossLog();  // Finishes if Finish was not called; errors are printed then.
  LossLog(const LossLog&) = delete;
  LossLog& operator=(const LossLog&) = delete;

  void Add(const mac::TraceEvent& event);
  // `sink` (may be null; outlives this) is told each second's rows once no transmission can
  // still add to them: when an event of 50 ms past the second's end has come (a frame is on
  // the air for under 20 ms), and at Finish.
  void SetLiveSink(LiveSink* sink) { live_ = sink; }
  // Ends losses.csv.gz and writes links.csv. Throws Error naming a file.
  void Finish();
  const DeliveryByLinkClass& delivery_by_link_class() const { return by_link_class_; }

 private:
  struct Counts;
  int StationOf(const MacAddress& mac) const;
  void AddTransmission(const mac::TxRecord& tx);
  void Deflate(int flush);
  Counts& Link(TimeNs time_ns, int from, int to);
  static LinkRow RowOf(uint64_t key, const Counts& counts);
  // Tells live_ of the seconds that end 50 ms or more before `time_ns`.
  void PublishSecondsBefore(TimeNs time_ns);

  std::string run_dir_;
  std::vector<MacAddress> stations_;
  double noise_floor_dbm_, detect_min_rssi_dbm_;
  std::unique_ptr<LineFile> file_;
  struct ZStream;
  std::unique_ptr<ZStream> z_;
  std::string pending_;  // CSV text not yet deflated.
  // Key: second << 32 | (from + 1) << 16 | (to + 1) (to is -1 for group frames).
  std::unordered_map<uint64_t, Counts> links_;
  DeliveryByLinkClass by_link_class_;
  bool finished_ = false;
  LiveSink* live_ = nullptr;
  int64_t next_live_second_ = 0;
  std::vector<uint64_t> live_keys_;  // Keys of links_ made since their second was told.
};

// The LossLog of a run of `scenario` in `run_dir`: its robots' MACs, its radio's noise floor and
// preamble threshold.
std::unique_ptr<LossLog> MakeLossLog(const std::string& run_dir, const Scenario& scenario);

//----------------------------- What a robot's log says (log_cause.cc) -----------------------------
// What a robot's log says went wrong, quoted in the one line that reports a robot that could
// not start (runner/robot_start.cc): the user learns the cause without opening the log.

// The first line of `log` that reads like an error (error, panic, fatal, fail, denied, not
// found, no such, cannot, unrecognized, invalid; any case), else its last non-empty line, else
// "". For a program that exited: its first complaint is the cause, what follows is fallout (a
// usage text, a stack dump). Trimmed, control characters dropped, at most 200 characters.
std::string FirstErrorLine(const std::string& log);

// The last non-empty line of `log` (trimmed and cut as above), or "". For a program that still
// runs: its latest line says what it waits for (PX4: "Waiting for simulator to accept connection
// on TCP port 4561").
std::string LastLine(const std::string& log);

// The log file's text, at most its last `max_bytes` (a long boot log keeps its end).
std::string ReadLogTail(const std::string& path, size_t max_bytes = 1 << 20);

// "; its log says \"LINE\"" for a line, "" for none: appended to an error message.
std::string LogSays(const std::string& line);

}  // namespace sitlnet::run_formats

#endif  // SITLNET_RUN_FORMATS_RUN_FORMATS_H_
