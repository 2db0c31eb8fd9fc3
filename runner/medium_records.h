// The medium's records of a run, fed by the bridge as frames cross the air: medium.pcap,
// deliveries.csv, and the communication graph over time (for connectivity.csv).
#ifndef SITLNET_RUNNER_MEDIUM_RECORDS_H_
#define SITLNET_RUNNER_MEDIUM_RECORDS_H_

#include <string>

#include "common/common.h"
#include "run_formats/run_formats.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

class MediumRecords {
 public:
  // Creates <run_dir>/medium.pcap (with its file header) and <run_dir>/deliveries.csv; throws
  // Error naming the file. pcap timestamps are virtual in lockstep, so that runs are
  // byte-identical, and wall-clock dates in realtime.
  // `losses` (may be null; outlives this): losses.csv.gz and links.csv, finished by Flush.
  MediumRecords(const std::string& run_dir, int robots, bool lockstep,
                run_formats::LossLog* losses);
  // Records every air frame and delivery of `bridge` from now on; this must outlive its use.
  void Attach(tapbridge::BridgeCore* bridge);
  run_formats::ConnectivityTracker& connectivity() { return connectivity_; }
  // The loss log (losses.csv.gz, links.csv), or null when the run records no losses.
  const run_formats::LossLog* losses() const { return losses_; }
  // deliveries.csv, medium.pcap, then the loss log; throws Error naming the file that cannot
  // be written.
  void Flush();

 private:
  LineFile pcap_;
  TimeNs epoch_offset_ns_;
  LineFile deliveries_;
  run_formats::ConnectivityTracker connectivity_;
  run_formats::LossLog* losses_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_MEDIUM_RECORDS_H_
