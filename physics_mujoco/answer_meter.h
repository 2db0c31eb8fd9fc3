// Counts an autopilot's answers for AutopilotRate (physics_mujoco.h): the physics thread writes
// (Answered), any thread reads (Read), without a lock.
#ifndef SITLNET_PHYSICS_MUJOCO_ANSWER_METER_H_
#define SITLNET_PHYSICS_MUJOCO_ANSWER_METER_H_

#include <atomic>
#include <cstdint>

#include "physics_mujoco/physics_mujoco.h"

namespace sitlnet::physics {

class AnswerMeter {
 public:
  // `count` answers came now (CLOCK_MONOTONIC `wall_ns`), from an autopilot that asks for
  // `nominal_hz`. One writer.
  void Answered(uint64_t count, double nominal_hz, TimeNs wall_ns) {
    if (count == 0) return;
    if (first_wall_ns_.load(std::memory_order_relaxed) < 0) {
      first_wall_ns_.store(wall_ns, std::memory_order_relaxed);
    }
    last_wall_ns_.store(wall_ns, std::memory_order_relaxed);
    nominal_hz_.store(nominal_hz, std::memory_order_relaxed);
    // Last, with release: a reader that sees the count sees the times written before it.
    answers_.store(answers_.load(std::memory_order_relaxed) + count, std::memory_order_release);
  }

  AutopilotRate Read() const {
    AutopilotRate rate;
    rate.answers = answers_.load(std::memory_order_acquire);
    rate.first_answer_wall_ns = first_wall_ns_.load(std::memory_order_relaxed);
    rate.last_answer_wall_ns = last_wall_ns_.load(std::memory_order_relaxed);
    rate.nominal_hz = nominal_hz_.load(std::memory_order_relaxed);
    return rate;
  }

 private:
  std::atomic<uint64_t> answers_{0};
  std::atomic<TimeNs> first_wall_ns_{-1};
  std::atomic<TimeNs> last_wall_ns_{-1};
  std::atomic<double> nominal_hz_{0};
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_ANSWER_METER_H_
