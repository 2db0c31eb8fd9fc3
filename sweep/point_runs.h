// The sweep's runs: each point a `sitlnet run` child process in a job slot, at most `jobs` at
// once, stopped with SIGINT on the sweep's own SIGINT/SIGTERM.
#ifndef SITLNET_SWEEP_POINT_RUNS_H_
#define SITLNET_SWEEP_POINT_RUNS_H_

#include <functional>
#include <string>
#include <vector>

namespace sitlnet::sweep {

// One child to start: its argv, and the file its stdout and stderr go to.
struct PointCommand {
  std::vector<std::string> argv;
  std::string log_path;
};

// How a child ended: exit status (128 + N for signal N).
struct PointExit {
  size_t index = 0;  // Into the commands.
  int slot = 0;
  int status = 0;
  bool stopped = false;  // Ended after the sweep forwarded a stop.
};

// Runs `count` commands, at most `jobs` at once. `prepare(index, slot)` writes the point's input
// for that job slot and returns its command; `done` is called as each child ends. If either (or
// starting a child) throws Error, the running children get SIGINT and are waited for, then the
// first Error is thrown again. Returns true if a SIGINT/SIGTERM stopped it:
// then every running child got SIGINT and was waited for, and no new one started.
bool RunPoints(size_t count, int jobs,
               const std::function<PointCommand(size_t index, int slot)>& prepare,
               const std::function<void(const PointExit&)>& done);

}  // namespace sitlnet::sweep

#endif  // SITLNET_SWEEP_POINT_RUNS_H_
