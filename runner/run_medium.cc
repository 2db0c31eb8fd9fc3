#include "runner/run_medium.h"

namespace sitlnet::runner {

RunMedium::RunMedium(const Scenario& scenario, const RunOptions& options,
                     const std::string& run_dir, std::unique_ptr<network_side::RemoteMedium> remote,
                     std::function<std::unique_ptr<tapbridge::Port>(int robot)> open_port) {
  const bool lockstep = scenario.lockstep();
  tapbridge::BridgeOptions bridge_options;
  bridge_options.seed = scenario.spec.timing().seed();
  bridge_options.open_port = std::move(open_port);
  std::unique_ptr<tapbridge::MediumModel> medium;
  if (remote) {
    remote_medium_ = remote.get();
    medium = std::move(remote);
  } else {
    medium = tapbridge::MakeMacPhySimMedium(scenario);
    if (options.record_losses) {
      loss_log_ = run_formats::MakeLossLog(run_dir, scenario);
      loss_log_->SetLiveSink(options.live);
      medium->SetTraceSink([log = loss_log_.get()](const mac::TraceEvent& e) { log->Add(e); });
    }
  }
  bridge_ = std::make_unique<tapbridge::BridgeCore>(scenario, std::move(medium), bridge_options);
  bridge_->AttachAll();
  records_ = std::make_unique<MediumRecords>(run_dir, static_cast<int>(scenario.robots.size()),
                                             lockstep, loss_log_.get());
  records_->connectivity().SetLiveSink(options.live);
  records_->Attach(bridge_.get());
}

}  // namespace sitlnet::runner
