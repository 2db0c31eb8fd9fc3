#include "runner/run_stages.h"

namespace sitlnet::runner {

void RunStages::Run() {
  Refuse();
  PrepareHost();
  stop_.emplace();
  if (!Open(stop_->fd())) return;
  SetUp();
  if (!Loop(stop_->fd())) return;
  Stop();
  Report();
}

}  // namespace sitlnet::runner
