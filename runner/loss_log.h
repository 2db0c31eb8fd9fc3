// losses.csv.gz and links.csv of a run folder (docs/run.md): what happened to
// every frame at every station it reached above the noise floor, and every
// frame its sender dropped, as the 802.11 model decided it (mac_phy_sim's
// trace with EnableCauses); and per second and link, the delivery ratio and
// the main cause of loss.
#ifndef SITLNET_RUNNER_LOSS_LOG_H_
#define SITLNET_RUNNER_LOSS_LOG_H_

#include <unordered_map>
#include <memory>
#include <string>
#include <vector>

#include "common/common.h"
#include "mac_phy_sim/mac_phy_sim.h"
#include "runner/live_sink.h"
#include "scenario/scenario.h"

namespace sitlnet::runner {

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

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_LOSS_LOG_H_
