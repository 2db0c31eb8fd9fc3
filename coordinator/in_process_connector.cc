// In-process connectors: the simulator is called directly, on a worker
// thread (so physics and network overlap) or on the coordinator's thread.
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
  end->set_busy_ns(MonotonicNowNs() - begin);
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
  OwnThreadConnector(std::string name, Role role, Simulator* simulator)
      : Connector(std::move(name), role),
        simulator_(*simulator),
        poses_(simulator->InitialPoses()),
        worker_([this] { Work(); }) {}

  ~OwnThreadConnector() override {
    {
      std::lock_guard lock(mutex_);
      quit_ = true;
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
    }
    changed_.notify_all();
  }

  void Work() {
    std::unique_lock lock(mutex_);
    for (;;) {
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
      changed_.notify_all();
    }
  }

  Simulator& simulator_;
  proto::coord::Poses poses_;
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

std::string RoleName(Role role) { return role == Role::kPhysics ? "physics" : "network"; }

std::string Connector::Describe() const { return RoleName(role_) + " connector '" + name_ + "'"; }

std::unique_ptr<Connector> MakeInProcessConnector(std::string name, Role role, Simulator* simulator,
                                                  Threading threading) {
  if (threading == Threading::kCallerThread) {
    return std::make_unique<CallerThreadConnector>(std::move(name), role, simulator);
  }
  return std::make_unique<OwnThreadConnector>(std::move(name), role, simulator);
}

}  // namespace sitlnet::coordinator
