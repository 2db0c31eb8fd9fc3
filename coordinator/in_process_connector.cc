// In-process connectors: the simulator is called directly, on a worker
// thread (so physics and network overlap) or on the coordinator's thread.
#include <pthread.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <exception>
#include <mutex>
#include <thread>

#include "coordinator/connector.h"

namespace sitlnet::coordinator {
namespace {

std::string Ms(TimeNs ns) { return std::to_string(ns / kNsPerMs) + " ms"; }

// Runs one iteration, timing it and turning exceptions into a message.
void RunOne(Simulator& simulator, const proto::coord::Start& start, proto::coord::End* end,
            IterationContext& context, std::string* error) {
  end->Clear();
  const TimeNs begin = MonotonicNowNs();
  try {
    simulator.RunIteration(start, end, context);
  } catch (const std::exception& e) {
    *error = e.what();
  }
  if (end->busy_ns() == 0) end->set_busy_ns(MonotonicNowNs() - begin);  // Unless it set its own.
  end->set_iteration(start.iteration());
}

class CallerThreadConnector final : public Connector, private IterationContext {
 public:
  CallerThreadConnector(std::string name, Role role, Simulator* simulator)
      : Connector(std::move(name), role),
        simulator_(*simulator),
        poses_(simulator->InitialPoses()) {}
  const proto::coord::Poses& initial_poses() const override { return poses_; }
  void Begin(const proto::coord::Start& start, const WaitLimits&) override { start_ = start; }
  bool runs_on_caller_thread() const override { return true; }
  bool AwaitCommandsCollected(uint64_t, const WaitLimits&) override {
    throw Error(Describe() +
                " runs on the coordinator's thread and cannot report "
                "CommandsCollected mid-iteration; use Threading::kOwnThread");
  }
  bool Finish(uint64_t iteration, proto::coord::End* end, const WaitLimits&) override {
    std::string error;
    RunOne(simulator_, start_, end, *this, &error);
    if (!error.empty()) {
      throw Error(Describe() + " failed in iteration " + std::to_string(iteration) + ": " + error);
    }
    return true;
  }
  void Stop(const std::string&) override {}

 private:
  void CommandsCollected() override {}
  Simulator& simulator_;
  proto::coord::Poses poses_;
  proto::coord::Start start_;
};

class OwnThreadConnector final : public Connector, private IterationContext {
 public:
  OwnThreadConnector(std::string name, Role role, Simulator* simulator, TimeNs spin_ns)
      : Connector(std::move(name), role),
        simulator_(*simulator),
        spin_ns_(spin_ns),
        poses_(simulator->InitialPoses()),
        worker_([this] { Work(); }) {}

  ~OwnThreadConnector() override {
    {
      std::lock_guard lock(mutex_);
      quit_ = true;
      version_.fetch_add(1, std::memory_order_release);
    }
    changed_.notify_all();
    worker_.join();
  }

  const proto::coord::Poses& initial_poses() const override { return poses_; }

  void Begin(const proto::coord::Start& start, const WaitLimits&) override {
    {
      std::lock_guard lock(mutex_);
      start_ = start;
      has_job_ = true;
      done_ = false;
      commands_collected_ = false;
      version_.fetch_add(1, std::memory_order_release);
    }
    changed_.notify_all();
  }

  bool AwaitCommandsCollected(uint64_t iteration, const WaitLimits& limits) override {
    return WaitFor(iteration, "CommandsCollected", limits,
                   [this] { return commands_collected_ || done_; });
  }

  bool Finish(uint64_t iteration, proto::coord::End* end, const WaitLimits& limits) override {
    if (!WaitFor(iteration, "END", limits, [this] { return done_; })) return false;
    std::lock_guard lock(mutex_);
    if (!error_.empty()) {
      throw Error(Describe() + " failed in iteration " + std::to_string(iteration) + ": " + error_);
    }
    end->Swap(&end_);
    return true;
  }

  void Stop(const std::string&) override {}

 private:
  template <typename Ready>
  bool WaitFor(uint64_t iteration, const char* what, const WaitLimits& limits, Ready ready) {
    SpinWhileUnchanged(version_.load(std::memory_order_acquire), ready);
    std::unique_lock lock(mutex_);
    // The interrupt fd is not polled here: an in-process iteration ends by
    // itself, and the deadline bounds the wait.
    const auto until = std::chrono::steady_clock::time_point(std::chrono::nanoseconds(
        limits.deadline_ns == kNoDeadline ? INT64_MAX / 2 : limits.deadline_ns));
    // steady_clock is CLOCK_MONOTONIC on Linux, the clock of deadline_ns.
    if (!changed_.wait_until(lock, until, ready)) {
      throw Error(Describe() + " did not answer START of iteration " + std::to_string(iteration) +
                  " with " + what + " within " + Ms(limits.timeout_ns));
    }
    return true;
  }

  void CommandsCollected() override {
    {
      std::lock_guard lock(mutex_);
      commands_collected_ = true;
      version_.fetch_add(1, std::memory_order_release);
    }
    changed_.notify_all();
  }

  // Spins (without the lock) until the state changed and `ready` holds, or
  // spin_ns_ passed: a sleeping thread takes tens of µs to wake on this
  // machine class, a spinning one about one (docs/performance.md).
  template <typename Ready>
  void SpinWhileUnchanged(uint32_t seen, Ready ready) {
    if (spin_ns_ <= 0) return;
    const TimeNs until = MonotonicNowNs() + spin_ns_;
    for (;;) {
      const uint32_t now_version = version_.load(std::memory_order_acquire);
      if (now_version != seen) {
        std::lock_guard lock(mutex_);
        if (ready()) return;
        seen = now_version;
      }
      if (MonotonicNowNs() >= until) return;
      __builtin_ia32_pause();
    }
  }

  void Work() {
    // Named after the connector ("sitlnet-physics"): benchmarks and top find it by name.
    pthread_setname_np(pthread_self(), ("sitlnet-" + name()).substr(0, 15).c_str());
    std::unique_lock lock(mutex_);
    for (;;) {
      if (!quit_ && !has_job_) {
        const uint32_t seen = version_.load(std::memory_order_acquire);
        lock.unlock();
        SpinWhileUnchanged(seen, [this] { return quit_ || has_job_; });
        lock.lock();
      }
      changed_.wait(lock, [this] { return quit_ || has_job_; });
      if (quit_) return;
      has_job_ = false;
      proto::coord::Start start = start_;
      lock.unlock();
      proto::coord::End end;
      std::string error;
      RunOne(simulator_, start, &end, *this, &error);
      lock.lock();
      end_.Swap(&end);
      error_ = std::move(error);
      done_ = true;
      version_.fetch_add(1, std::memory_order_release);
      changed_.notify_all();
    }
  }

  Simulator& simulator_;
  TimeNs spin_ns_;
  proto::coord::Poses poses_;
  std::atomic<uint32_t> version_{0};  // Bumped (under mutex_) on every state change.
  std::mutex mutex_;
  std::condition_variable changed_;
  bool quit_ = false;
  bool has_job_ = false;
  bool done_ = false;
  bool commands_collected_ = false;
  proto::coord::Start start_;
  proto::coord::End end_;
  std::string error_;
  std::thread worker_;  // Last: starts after every other member exists.
};

}  // namespace

std::string RoleName(Role role) {
  return role == Role::kPhysics ? "physics" : role == Role::kNetwork ? "network" : "node";
}

std::string Connector::Describe() const {
  return description_.empty() ? RoleName(role_) + " connector '" + name_ + "'" : description_;
}

std::unique_ptr<Connector> MakeInProcessConnector(std::string name, Role role, Simulator* simulator,
                                                  Threading threading, TimeNs spin_ns) {
  if (threading == Threading::kCallerThread) {
    return std::make_unique<CallerThreadConnector>(std::move(name), role, simulator);
  }
  return std::make_unique<OwnThreadConnector>(std::move(name), role, simulator, spin_ns);
}

}  // namespace sitlnet::coordinator
