#include "runner/iteration_observer.h"

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "common/common.h"

namespace sitlnet::runner {
namespace {

// Writes what happens, in order, to one shared log.
class LoggingSimulator final : public coordinator::Simulator {
 public:
  explicit LoggingSimulator(std::vector<std::string>* log) : log_(*log) {}
  proto::coord::Poses InitialPoses() override {
    proto::coord::Poses poses;
    poses.add_position_m(7);
    return poses;
  }
  void RunIteration(const proto::coord::Start& start, proto::coord::End*,
                    coordinator::IterationContext&) override {
    log_.push_back("run " + std::to_string(start.start_ns()));
  }

 private:
  std::vector<std::string>& log_;
};

class LoggingObserver final : public IterationObserver {
 public:
  LoggingObserver(std::string name, std::vector<std::string>* log, TimeNs fail_at_end_ns = -1)
      : name_(std::move(name)), log_(*log), fail_at_end_ns_(fail_at_end_ns) {}
  void IterationBegins(const proto::coord::Start& start) override {
    log_.push_back(name_ + " begins " + std::to_string(start.start_ns()));
  }
  void IterationEnded(const proto::coord::Start& start) override {
    log_.push_back(name_ + " ended " + std::to_string(start.end_ns()));
    if (start.end_ns() == fail_at_end_ns_) throw Error(name_ + " stops the run");
  }

 private:
  std::string name_;
  std::vector<std::string>& log_;
  TimeNs fail_at_end_ns_;
};

class NoContext final : public coordinator::IterationContext {
 public:
  void CommandsCollected() override {}
};

proto::coord::Start Iteration(TimeNs start_ns, TimeNs end_ns) {
  proto::coord::Start start;
  start.set_start_ns(start_ns);
  start.set_end_ns(end_ns);
  return start;
}

TEST(IterationObserverTest, ObserversAreToldBeforeAndAfterEachIterationInTheirOrder) {
  std::vector<std::string> log;
  LoggingSimulator inner(&log);
  LoggingObserver first("first", &log), second("second", &log);
  ObservedSimulator observed(&inner, {&first, &second});
  NoContext context;
  proto::coord::End end;
  observed.RunIteration(Iteration(0, 10), &end, context);
  observed.RunIteration(Iteration(10, 20), &end, context);
  EXPECT_EQ(
      log, (std::vector<std::string>{"first begins 0", "second begins 0", "run 0", "first ended 10",
                                     "second ended 10", "first begins 10", "second begins 10",
                                     "run 10", "first ended 20", "second ended 20"}));
  EXPECT_EQ(observed.InitialPoses().position_m_size(), 1);  // The inner simulator's.
}

TEST(IterationObserverTest, AnObserversErrorEndsTheIterationAndReachesTheCaller) {
  std::vector<std::string> log;
  LoggingSimulator inner(&log);
  LoggingObserver stopper("stopper", &log, 20), after("after", &log);
  ObservedSimulator observed(&inner, {&stopper, &after});
  NoContext context;
  proto::coord::End end;
  observed.RunIteration(Iteration(0, 10), &end, context);
  log.clear();
  try {
    observed.RunIteration(Iteration(10, 20), &end, context);
    FAIL() << "no Error";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(), "stopper stops the run");
  }
  // The inner simulator ran the iteration; the observers after the failing one were not told.
  EXPECT_EQ(log, (std::vector<std::string>{"stopper begins 10", "after begins 10", "run 10",
                                           "stopper ended 20"}));
}

}  // namespace
}  // namespace sitlnet::runner
