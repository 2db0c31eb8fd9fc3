// Realtime scheduling of the harness's own loops (common.h, "Scheduling").
#include <sched.h>

#include <cerrno>
#include <string>

#include "common/common.h"

namespace sitlnet {

std::string RequestRealtimePriority(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  // pid 0: the calling thread only (Linux schedules threads); later threads inherit the policy.
  if (sched_setscheduler(0, SCHED_FIFO, &param) == 0) return "";
  return SystemErrorMessage("SCHED_FIFO priority " + std::to_string(priority) +
                                " refused (needs CAP_SYS_NICE), running with normal priority",
                            errno);
}

void ResetToNormalScheduling() {
  sched_param param{};
  param.sched_priority = 0;
  sched_setscheduler(0, SCHED_OTHER, &param);
}

}  // namespace sitlnet
