// What a robot's log says went wrong, quoted in the one line that reports a robot that could
// not start (runner/robot_start.cc): the user learns the cause without opening the log.
#ifndef SITLNET_RUNNER_LOG_CAUSE_H_
#define SITLNET_RUNNER_LOG_CAUSE_H_

#include <string>

namespace sitlnet::runner {

// The first line of `log` that reads like an error (error, panic, fatal, fail, denied, not
// found, no such, cannot, unrecognized, invalid; any case), else its last non-empty line, else
// "". For a program that exited: its first complaint is the cause, what follows is fallout (a
// usage text, a stack dump). Trimmed, control characters dropped, at most 200 characters.
std::string FirstErrorLine(const std::string& log);

// The last non-empty line of `log` (trimmed and cut as above), or "". For a program that still
// runs: its latest line says what it waits for (PX4: "Waiting for simulator to accept connection
// on TCP port 4561").
std::string LastLine(const std::string& log);

// The log file's text, at most its last `max_bytes` (a long boot log keeps its end).
std::string ReadLogTail(const std::string& path, size_t max_bytes = 1 << 20);

// "; its log says \"LINE\"" for a line, "" for none: appended to an error message.
std::string LogSays(const std::string& line);

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_LOG_CAUSE_H_
