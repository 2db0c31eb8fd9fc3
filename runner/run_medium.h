// The medium of a run: the 802.11 model (in this process, or accepted from another host), the
// bridge between it and the robots' ports, and the medium's records (medium.pcap,
// deliveries.csv, connectivity, the loss log). The same on one host and on a fleet's central host.
#ifndef SITLNET_RUNNER_RUN_MEDIUM_H_
#define SITLNET_RUNNER_RUN_MEDIUM_H_

#include <functional>
#include <memory>
#include <string>

#include "network_side/network_side.h"
#include "run_formats/run_formats.h"
#include "runner/medium_records.h"
#include "runner/runner.h"
#include "scenario/scenario.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::runner {

class RunMedium {
 public:
  // Makes the medium (`remote`, or the scenario's model here, its losses logged unless
  // options.record_losses is off), the bridge over the ports `open_port` opens (empty: the
  // robots' TAPs) with every robot attached, and the records. Throws Error naming a file.
  RunMedium(const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
            std::unique_ptr<network_side::RemoteMedium> remote,
            std::function<std::unique_ptr<tapbridge::Port>(int robot)> open_port = {});
  RunMedium(const RunMedium&) = delete;
  RunMedium& operator=(const RunMedium&) = delete;

  tapbridge::BridgeCore& bridge() { return *bridge_; }
  MediumRecords& records() { return *records_; }
  // The medium on another host (owned by the bridge), or null.
  network_side::RemoteMedium* remote_medium() { return remote_medium_; }

 private:
  network_side::RemoteMedium* remote_medium_ = nullptr;
  std::unique_ptr<run_formats::LossLog> loss_log_;  // Outlives the bridge: its medium writes to it.
  std::unique_ptr<tapbridge::BridgeCore> bridge_;
  std::unique_ptr<MediumRecords> records_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_RUN_MEDIUM_H_
