#include "runner/recording_connector.h"

namespace sitlnet::runner {

RecordingConnector::RecordingConnector(coordinator::Connector* inner,
                                       const physics::GeodeticFrame& frame,
                                       const std::string& csv_path, TimeNs period_ns)
    : coordinator::Connector(inner->name(), inner->role(), inner->Describe()),
      inner_(*inner),
      recorder_(frame, csv_path),
      period_ns_(period_ns) {}

void RecordingConnector::Begin(const proto::coord::Start& start,
                               const coordinator::WaitLimits& limits) {
  if (start.start_ns() == 0) recorder_.Record(0, inner_.initial_poses());
  end_ns_ = start.end_ns();
  inner_.Begin(start, limits);
}

bool RecordingConnector::Finish(uint64_t iteration, proto::coord::End* end,
                                const coordinator::WaitLimits& limits) {
  if (!inner_.Finish(iteration, end, limits)) return false;
  if (end_ns_ >= next_sample_ns_ + period_ns_) {
    recorder_.Record(end_ns_, end->poses());
    next_sample_ns_ = end_ns_;
  }
  return true;
}

}  // namespace sitlnet::runner
