// Realtime flights of the real autopilots, judged on a host that let them keep real time. An
// autopilot in realtime pacing must run within each millisecond of wall time; on a shared host a
// neighbour can take the CPU (CI: ArduCopter said "Main loop slow (309Hz < 400Hz)" at a load
// average of 0.6; here, with two compilers beside it, PX4's estimate was 0.76 m off and
// ArduCopter's altitude 0.66 m). Such a flight says nothing about sitlnet, so it is flown once
// more, and the second flight is judged whatever the host did (docs/autopilots-evidence.md).
#ifndef SITLNET_TESTS_INTEGRATION_REALTIME_JUDGE_H_
#define SITLNET_TESTS_INTEGRATION_REALTIME_JUDGE_H_

#include <functional>

namespace sitlnet::integration_test {

// Runs `flight(may_fly_again)`: a flight and its gtest checks. It returns true when the autopilot
// itself said the host starved it and it checked nothing (it may only when `may_fly_again`). The
// flight is flown once more when it says so, or when its checks failed while the host's CPUs
// were more than half busy or more than 5 % stolen by a hypervisor (this test's own processes
// take about a sixth). The first flight's failures are then printed, not counted.
void FlyJudgedOnAHostThatKeptUp(const std::function<bool(bool may_fly_again)>& flight);

// Lockstep flights: the host's load is no excuse (the run waits for the autopilot), but an
// autopilot's own race may be. The flight is flown once more only when it says it was starved.
void FlyAgainIfTheAutopilotSaysItWasStarved(const std::function<bool(bool may_fly_again)>& flight);

}  // namespace sitlnet::integration_test

#endif  // SITLNET_TESTS_INTEGRATION_REALTIME_JUDGE_H_
