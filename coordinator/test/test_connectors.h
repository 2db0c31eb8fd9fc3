// Helpers shared by the coordinator's unit tests: synthetic connectors on
// threads behind real sockets, and the usual options.
#ifndef SITLNET_COORDINATOR_TEST_TEST_CONNECTORS_H_
#define SITLNET_COORDINATOR_TEST_TEST_CONNECTORS_H_

#include <string>
#include <thread>

#include "coordinator/coordinator.h"
#include "coordinator/synthetic.h"

namespace sitlnet::coordinator::test_support {

inline constexpr TimeNs kDelta = 10 * kNsPerMs;
inline constexpr uint64_t kHash = 0x5117'0e70'0000'0001ull;

inline SyntheticOptions Robots(int robots) {
  SyntheticOptions options;
  options.robots = robots;
  options.step_ns = kDelta;
  return options;
}

inline CoordinatorOptions Lockstep(int64_t iterations) {
  CoordinatorOptions options;
  options.iteration_ns = kDelta;
  options.iterations = iterations;
  options.pacing = Pacing::kLockstep;
  options.answer_timeout_ns = 5 * kNsPerS;
  return options;
}

// The network at iteration k must see the poses physics reported at kΔ.

class ConnectorThread {
 public:
  ConnectorThread(Endpoint endpoint, Simulator* simulator, ConnectorIdentity identity)
      : thread_([=, this] {
          try {
            Channel channel(Connect(endpoint, MonotonicNowNs() + 5 * kNsPerS));
            stop_reason_ = ServeCoordinator(channel, *simulator, identity, 5 * kNsPerS);
          } catch (const Error& e) {
            error_ = e.what();
          }
        }) {}
  ~ConnectorThread() { Join(); }
  void Join() {
    if (thread_.joinable()) thread_.join();
  }
  const std::string& error() const { return error_; }
  const std::string& stop_reason() const { return stop_reason_; }

 private:
  std::string error_;
  std::string stop_reason_;
  std::thread thread_;
};

inline HandshakeExpectation Expect() {
  HandshakeExpectation expect;
  expect.scenario_hash = kHash;
  expect.iteration_ns = kDelta;
  return expect;
}

inline WaitLimits Within(TimeNs timeout_ns) {
  WaitLimits limits;
  limits.timeout_ns = timeout_ns;
  limits.deadline_ns = MonotonicNowNs() + timeout_ns;
  return limits;
}

}  // namespace sitlnet::coordinator::test_support

#endif  // SITLNET_COORDINATOR_TEST_TEST_CONNECTORS_H_
