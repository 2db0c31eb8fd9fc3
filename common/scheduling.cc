// Realtime scheduling of the harness's own loops (common.h, "Scheduling").
#include <sched.h>

#include <atomic>
#include <cerrno>
#include <string>

#include "common/common.h"

namespace sitlnet {
namespace {

// Set once this process raised itself: only then do its children go back to SCHED_OTHER (a run
// started under `chrt -f` passes that policy on to its children, as any program does).
std::atomic<bool> g_raised_by_sitlnet{false};

}  // namespace

std::string RequestRealtimePriority(int priority) {
  // Already realtime (e.g. `chrt -f 20 sitlnet run ...`): the caller's choice stands.
  const int current = sched_getscheduler(0);
  if (current == SCHED_FIFO || current == SCHED_RR) return "";
  sched_param param{};
  param.sched_priority = priority;
  // pid 0: the calling thread only (Linux schedules threads); later threads inherit the policy.
  if (sched_setscheduler(0, SCHED_FIFO, &param) == 0) {
    g_raised_by_sitlnet.store(true);
    return "";
  }
  const int err = errno;
  return SystemErrorMessage("SCHED_FIFO priority " + std::to_string(priority) + " refused" +
                                (err == EPERM ? " (needs CAP_SYS_NICE or RLIMIT_RTPRIO)" : "") +
                                ", running with normal priority",
                            err);
}

void ResetToNormalScheduling() {
  if (!g_raised_by_sitlnet.load()) return;
  sched_param param{};
  param.sched_priority = 0;
  sched_setscheduler(0, SCHED_OTHER, &param);
}

}  // namespace sitlnet
