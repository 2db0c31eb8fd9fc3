#include "runner/recording_physics.h"

namespace sitlnet::runner {

RecordingPhysics::RecordingPhysics(coordinator::Simulator* inner,
                                   const physics::GeodeticFrame& frame, const std::string& csv_path,
                                   TimeNs period_ns)
    : inner_(*inner), recorder_(frame, csv_path), period_ns_(period_ns) {}

void RecordingPhysics::RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                                    coordinator::IterationContext& context) {
  if (start.start_ns() == 0) recorder_.Record(0, inner_.InitialPoses());
  inner_.RunIteration(start, end, context);
  if (shared_time_ != nullptr) shared_time_->Store(start.end_ns());
  if (start.end_ns() >= next_sample_ns_ + period_ns_) {
    recorder_.Record(start.end_ns(), end->poses());
    next_sample_ns_ = start.end_ns();
  }
}

}  // namespace sitlnet::runner
