// A fixed set of worker threads that run numbered tasks; the caller works too.
#ifndef SITLNET_PHYSICS_MUJOCO_STEP_POOL_H_
#define SITLNET_PHYSICS_MUJOCO_STEP_POOL_H_

#include <atomic>
#include <condition_variable>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace sitlnet::physics {

class StepPool {
 public:
  // `threads` >= 1 counts the caller: threads - 1 workers are started.
  explicit StepPool(int threads);
  ~StepPool();
  StepPool(const StepPool&) = delete;
  StepPool& operator=(const StepPool&) = delete;

  int threads() const { return static_cast<int>(workers_.size()) + 1; }

  // Runs task(0) .. task(count - 1) over the workers and the caller; returns when all ran.
  void Run(int count, const std::function<void(int)>& task);

 private:
  void WorkerLoop();
  void Drain();

  std::vector<std::thread> workers_;
  std::mutex mutex_;
  std::condition_variable start_;
  std::condition_variable done_;
  const std::function<void(int)>* task_ = nullptr;
  int count_ = 0;
  std::atomic<int> next_{0};
  int busy_ = 0;  // Workers still inside the current generation.
  unsigned generation_ = 0;
  bool stopping_ = false;
};

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_STEP_POOL_H_
