// A manual clock for pacing tests: time moves only when told, and a sleep
// jumps straight to its deadline (recorded), so tests never really sleep.
#ifndef SITLNET_COORDINATOR_TEST_FAKE_CLOCK_H_
#define SITLNET_COORDINATOR_TEST_FAKE_CLOCK_H_

#include <vector>

#include "coordinator/pacer.h"

namespace sitlnet::coordinator {

class FakeClock final : public clock::WallClock {
 public:
  explicit FakeClock(TimeNs now_ns = 1'000'000'000) : now_ns_(now_ns) {}
  TimeNs NowNs() override {
    const TimeNs now = now_ns_;
    now_ns_ += advance_per_read_ns_;
    return now;
  }
  void SleepUntilNs(TimeNs wall_ns) override {
    sleeps_.push_back(wall_ns);
    if (wall_ns > now_ns_) now_ns_ = wall_ns;
  }
  void Advance(TimeNs ns) { now_ns_ += ns; }
  // Every NowNs() call moves time on by this much (simulates work).
  void set_advance_per_read_ns(TimeNs ns) { advance_per_read_ns_ = ns; }
  const std::vector<TimeNs>& sleeps() const { return sleeps_; }

 private:
  TimeNs now_ns_;
  TimeNs advance_per_read_ns_ = 0;
  std::vector<TimeNs> sleeps_;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_TEST_FAKE_CLOCK_H_
