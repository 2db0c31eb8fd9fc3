#include "tests/integration/realtime_judge.h"

#include <gtest/gtest-spi.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "tests/integration/test_util.h"

namespace sitlnet::integration_test {
namespace {

constexpr double kBusyShare = 0.5;
constexpr double kStolenShare = 0.05;

bool Failed(const ::testing::TestPartResultArray& results) {
  for (int i = 0; i < results.size(); ++i) {
    if (results.GetTestPartResult(i).failed()) return true;
  }
  return false;
}

// The captured results go to the test as they would have: failures as failures, a skip as a skip.
void Report(const ::testing::TestPartResultArray& results) {
  for (int i = 0; i < results.size(); ++i) {
    const ::testing::TestPartResult& result = results.GetTestPartResult(i);
    if (result.skipped()) GTEST_SKIP() << result.message();
    if (!result.failed()) continue;
    ADD_FAILURE_AT(result.file_name() ? result.file_name() : "?", result.line_number())
        << result.message();
  }
}

// The first attempt's failures, at most five, one line each: shown, not counted.
void PrintHeldFailures(const ::testing::TestPartResultArray& results) {
  for (int i = 0; i < results.size() && i < 5; ++i) {
    const ::testing::TestPartResult& result = results.GetTestPartResult(i);
    if (!result.failed()) continue;
    std::string summary = result.summary();
    std::replace(summary.begin(), summary.end(), '\n', ' ');
    std::printf("  %s:%d: %.300s\n", result.file_name() ? result.file_name() : "?",
                result.line_number(), summary.c_str());
  }
  std::fflush(stdout);
}

// Runs `attempt` with its results held in `results`, not reported.
void RunHeld(const std::function<void()>& attempt, ::testing::TestPartResultArray* results) {
  const ::testing::ScopedFakeTestPartResultReporter intercept(
      ::testing::ScopedFakeTestPartResultReporter::INTERCEPT_ALL_THREADS, results);
  attempt();
}

// True if every failure held is a realtime bound's (kRealtimeBoundMark in its trace).
bool OnlyRealtimeBoundsFailed(const ::testing::TestPartResultArray& results) {
  for (int i = 0; i < results.size(); ++i) {
    const ::testing::TestPartResult& result = results.GetTestPartResult(i);
    if (result.failed() && std::string(result.message()).find(kRealtimeBoundMark) == std::string::npos) {
      return false;
    }
  }
  return true;
}

}  // namespace

void FlyJudgedOnAHostThatKeptUp(const std::function<bool(bool may_fly_again)>& flight) {
  const HostCpuWatch watch;
  ::testing::TestPartResultArray first;
  bool starved = false;
  RunHeld([&] { starved = flight(true); }, &first);
  const HostCpuWatch::Shares shares = watch.SharesUpToNow();
  const bool disturbed = shares.busy > kBusyShare || shares.stolen > kStolenShare;
  if (!starved && !(Failed(first) && disturbed)) {
    Report(first);
    return;
  }
  std::printf("[ host     ] the first flight %s while %s; flying once more. Its failures:\n",
              starved ? "was starved, said the autopilot," : "failed", HostLoad(&watch).c_str());
  PrintHeldFailures(first);
  flight(false);
}

void RunOnceMoreIfItFails(const std::function<void()>& attempt) {
  const HostCpuWatch watch;
  ::testing::TestPartResultArray first;
  RunHeld(attempt, &first);
  if (!Failed(first) || !OnlyRealtimeBoundsFailed(first)) {
    Report(first);
    return;
  }
  std::printf("[ host     ] a realtime bound failed while %s; running once more. Its failures:\n",
              HostLoad(&watch).c_str());
  PrintHeldFailures(first);
  attempt();
}

}  // namespace sitlnet::integration_test
