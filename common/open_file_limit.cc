// The open-file limit of a process that holds descriptors per robot (TAPs, sockets, pidfds).
#include <sys/resource.h>

#include <cerrno>
#include <string>

#include "common/common.h"

namespace sitlnet {

uint64_t RaiseOpenFileLimit(uint64_t needed, std::string_view what) {
  rlimit limit{};
  if (getrlimit(RLIMIT_NOFILE, &limit) != 0) {
    throw Error(SystemErrorMessage(std::string(what) + ": read the open-file limit", errno));
  }
  if (limit.rlim_cur != RLIM_INFINITY && limit.rlim_cur >= needed) return limit.rlim_cur;
  if (limit.rlim_max == RLIM_INFINITY || limit.rlim_max >= needed) {
    // The soft limit is the caller's to raise up to the hard one: no privilege needed.
    limit.rlim_cur = needed;
  } else {
    // Raising the hard limit needs CAP_SYS_RESOURCE (root has it; a container may not).
    limit.rlim_cur = limit.rlim_max = needed;
  }
  if (setrlimit(RLIMIT_NOFILE, &limit) != 0) {
    rlimit now{};
    getrlimit(RLIMIT_NOFILE, &now);
    throw Error(std::string(what) + " needs " + std::to_string(needed) +
                " open files, above the hard limit of " + std::to_string(now.rlim_max) +
                " (`ulimit -Hn`), which only CAP_SYS_RESOURCE may raise: raise it "
                "(e.g. `prlimit --nofile=" +
                std::to_string(needed) + " --pid $$`, or the container's --ulimit nofile=" +
                std::to_string(needed) + ") or run fewer robots");
  }
  return needed;
}

}  // namespace sitlnet
