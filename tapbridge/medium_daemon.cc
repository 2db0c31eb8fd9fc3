// The medium daemon's library call (its thin main: cli/medium_command.cc; the shape every daemon
// has: docs/architecture.md, "Processes"). It reads like a script: build the medium, attach the
// TAPs, open the outputs, serve the control socket, run the realtime loop until SIGINT/SIGTERM.
#include <signal.h>
#include <sys/epoll.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <cerrno>
#include <climits>
#include <cstdio>

#include "tapbridge/control_server.h"
#include "tapbridge/pcap_fanout.h"

namespace sitlnet::tapbridge {
namespace {

std::string Us(TimeNs ns) { return std::to_string(ns / kNsPerUs) + " us"; }

void MakeDirectories(const std::string& path) {
  for (size_t at = 1; at != std::string::npos; at = path.find('/', at + 1)) {
    mkdir(path.substr(0, at).c_str(), 0755);
  }
  mkdir(path.c_str(), 0755);
}

std::string CountersLine(const BridgeCore& core, int robot) {
  const PortCounters& p = core.port_counters(robot);
  const MediumCounters m = core.medium_counters(robot);
  std::string line = "robot " + core.scenario().robots[robot].name +
                     (p.attached ? "" : " (detached)") + ": sent " + std::to_string(m.sent) +
                     " delivered " + std::to_string(m.delivered) + " queue_drops " +
                     std::to_string(m.queue_drops) + " queue_expired " +
                     std::to_string(m.queue_expired);
  for (const auto& [reason, count] : m.lost) {
    if (count) line += " lost_" + reason + " " + std::to_string(count);
  }
  line +=
      " | read " + std::to_string(p.frames_read) + " written " + std::to_string(p.frames_written);
  if (p.oversize_dropped) line += " oversize_dropped " + std::to_string(p.oversize_dropped);
  if (p.runt_dropped) line += " runt_dropped " + std::to_string(p.runt_dropped);
  if (p.unknown_source_dropped) {
    line += " unknown_source_dropped " + std::to_string(p.unknown_source_dropped);
  }
  if (p.write_errors) line += " write_errors " + std::to_string(p.write_errors);
  if (p.kernel_tx_dropped) line += " tap_overflow " + std::to_string(p.kernel_tx_dropped);
  return line;
}

}  // namespace

int RunMediumDaemon(const Scenario& scenario, const DaemonOptions& options) {
  auto log = options.log ? options.log : [](const std::string& line) {
    std::fprintf(stderr, "sitlnet medium: %s\n", line.c_str());
    std::fflush(stderr);
  };
  std::vector<MacAddress> macs;
  for (const RobotPlan& robot : scenario.robots) macs.push_back(robot.wlan_mac);
  std::unique_ptr<MediumModel> medium =
      options.use_relay_medium ? MakeRelayMedium(macs) : MakeMacPhySimMedium(scenario);

  BridgeOptions bridge_options;
  bridge_options.seed = scenario.spec.timing().seed();
  bridge_options.log = log;
  bridge_options.spin_ns = options.spin_ns;
  BridgeCore core(scenario, std::move(medium), bridge_options);
  const std::string socket_path =
      options.control_socket.empty() ? ControlSocketPath(scenario.name) : options.control_socket;
  if (ControlSocketAnswers(socket_path)) {
    throw Error("a medium daemon already serves scenario " + scenario.name + " (" + socket_path +
                ")");
  }
  core.AttachAll();

  // SIGINT/SIGTERM arrive as events on the loop (the StopSignal's pipe): the loop ends
  // between batches, the destructors close the TAPs and remove the socket.
  StopSignal stop;

  if (options.realtime_priority > 0) {
    if (const std::string refused = RequestRealtimePriority(options.realtime_priority);
        !refused.empty()) {
      log(refused);
    }
  }

  EventLoop loop;
  clock::Timebase timebase(scenario.spec.timing().realtime_factor());
  timebase.Begin(MonotonicNowNs());
  PcapFanout fanout(clock::CalendarNsOfWall(timebase.wall_origin_ns()));
  if (!options.pcap_path.empty()) fanout.OpenFile(options.pcap_path);
  core.AddAirFrameObserver([&fanout](const AirFrame& frame) { fanout.OnFrame(frame); });
  core.SetAirFrameCapture(fanout.active());

  MakeDirectories(socket_path.substr(0, socket_path.rfind('/')));
  ControlServer server(socket_path, &loop, &core, &fanout);

  loop.Add(stop.fd(), EPOLLIN, [&](uint32_t) {
    log(std::string("stopping on ") + (stop.signal_number() == SIGINT ? "SIGINT" : "SIGTERM"));
    loop.Stop();
  });

  // A robot namespace removed under us (sitlnet down, ip netns del) is
  // reported at once (inotify on /run/netns) and that robot detached; the
  // others keep running. A robot whose namespace and TAP come back is
  // re-attached on the next stats tick.
  const UniqueFd inotify(inotify_init1(IN_NONBLOCK | IN_CLOEXEC));
  const int inotify_fd = inotify.get();
  if (inotify_fd >= 0 && inotify_add_watch(inotify_fd, "/run/netns", IN_DELETE) >= 0) {
    loop.Add(inotify_fd, EPOLLIN, [&](uint32_t) {
      alignas(inotify_event) char buffer[4096];
      for (;;) {
        const ssize_t n = read(inotify_fd, buffer, sizeof buffer);
        if (n <= 0) return;
        for (ssize_t at = 0; at < n;) {
          const auto* event = reinterpret_cast<const inotify_event*>(buffer + at);
          at += sizeof(inotify_event) + event->len;
          if (event->len == 0) continue;
          const std::string name(event->name);
          for (const RobotPlan& robot : scenario.robots) {
            if (robot.netns == name && core.port_counters(robot.index).attached) {
              core.Detach(robot.index, "namespace " + name + " was deleted");
            }
          }
        }
      }
    });
  }

  const UniqueFd stats(timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC));
  const int stats_fd = stats.get();
  itimerspec period{};
  period.it_interval.tv_sec = options.stats_interval_ns / kNsPerS;
  period.it_interval.tv_nsec = options.stats_interval_ns % kNsPerS;
  period.it_value = period.it_interval;
  timerfd_settime(stats_fd, 0, &period, nullptr);
  loop.Add(stats_fd, EPOLLIN, [&](uint32_t) {
    uint64_t expirations = 0;
    [[maybe_unused]] ssize_t n = read(stats_fd, &expirations, sizeof expirations);
    const LatenessStats lateness = core.TakeLateness();
    // Lag behind the wall clock: how late deliveries were written. Quiet
    // while nothing is delivered.
    if (lateness.count > 0)
      log("t=" + std::to_string(core.VirtualNowNs() / kNsPerMs) +
          " ms: " + std::to_string(lateness.count) + " deliveries, lateness p50 " +
          Us(lateness.p50_ns) + " p99 " + Us(lateness.p99_ns) + " max " + Us(lateness.max_ns));
    core.RefreshKernelCounters();
    for (int i = 0; i < core.robot_count(); ++i) {
      if (!core.port_counters(i).attached) {
        struct stat st {};
        if (stat(("/run/netns/" + scenario.robots[i].netns).c_str(), &st) == 0) core.Reattach(i);
      }
    }
  });

  log("scenario " + scenario.name + ": " + std::to_string(core.robot_count()) +
      " robots attached, realtime factor " +
      std::to_string(scenario.spec.timing().realtime_factor()) + ", control socket " + socket_path +
      (options.pcap_path.empty() ? "" : ", pcap " + options.pcap_path));
  core.StartRealtime(&loop, timebase);
  loop.Run();
  core.StopRealtime();  // Before `loop` goes out of scope (it was declared after `core`).

  core.RefreshKernelCounters();
  const LatenessStats total = core.TotalLateness();
  log("stopped at t=" + std::to_string(core.VirtualNowNs() / kNsPerMs) + " ms; " +
      std::to_string(total.count) + " deliveries, lateness p50 " + Us(total.p50_ns) + " p99 " +
      Us(total.p99_ns) + " max " + Us(total.max_ns));
  for (int i = 0; i < core.robot_count(); ++i) log(CountersLine(core, i));
  loop.Remove(stats_fd);
  if (inotify_fd >= 0) loop.Remove(inotify_fd);
  loop.Remove(stop.fd());
  return 0;
}

}  // namespace sitlnet::tapbridge
