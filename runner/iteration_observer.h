// Observers of the coordinator's iterations, and the simulator decorator that calls them.
// The run's robot supervisor and progress line are observers of the network side's iterations:
// the bridge is single-threaded and runs on the coordinator's thread, so an observer there may
// read the bridge, and an Error it throws fails the run as the network connector's failure.
#ifndef SITLNET_RUNNER_ITERATION_OBSERVER_H_
#define SITLNET_RUNNER_ITERATION_OBSERVER_H_

#include <vector>

#include "coordinator/connector.h"

namespace sitlnet::runner {

class IterationObserver {
 public:
  virtual ~IterationObserver() = default;
  // Before the observed simulator runs the iteration [start.start_ns(), start.end_ns()).
  virtual void IterationBegins(const proto::coord::Start& /*start*/) {}
  // Once the observed simulator has run it. Throw Error to stop the run.
  virtual void IterationEnded(const proto::coord::Start& start) = 0;
};

// `inner`, with `observers` told of each of its iterations, in their order.
class ObservedSimulator final : public coordinator::Simulator {
 public:
  // `inner` and every observer must outlive this.
  ObservedSimulator(coordinator::Simulator* inner, std::vector<IterationObserver*> observers)
      : inner_(*inner), observers_(std::move(observers)) {}
  proto::coord::Poses InitialPoses() override { return inner_.InitialPoses(); }
  void RunIteration(const proto::coord::Start& start, proto::coord::End* end,
                    coordinator::IterationContext& context) override {
    for (IterationObserver* observer : observers_) observer->IterationBegins(start);
    inner_.RunIteration(start, end, context);
    for (IterationObserver* observer : observers_) observer->IterationEnded(start);
  }

 private:
  coordinator::Simulator& inner_;
  std::vector<IterationObserver*> observers_;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_ITERATION_OBSERVER_H_
