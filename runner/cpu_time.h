// CPU time read from getrusage(2), for the run's resources (summary.json).
#ifndef SITLNET_RUNNER_CPU_TIME_H_
#define SITLNET_RUNNER_CPU_TIME_H_

#include <sys/resource.h>

namespace sitlnet::runner {

// user+sys seconds of `who` (RUSAGE_SELF: all threads; RUSAGE_CHILDREN: the reaped children).
inline double CpuSeconds(int who) {
  rusage usage{};
  getrusage(who, &usage);
  return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
         static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
}

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_CPU_TIME_H_
