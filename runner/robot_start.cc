#include "runner/robot_start.h"

#include <google/protobuf/text_format.h>
#include <poll.h>
#include <sched.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#include "run_formats/run_formats.h"
#include "runner/boot_progress.h"

namespace sitlnet::runner {
namespace {

// Folder of the sitlnet binary (${SITLNET_BIN}; the flocker and ros2_clock programs are there).
std::string BinDir(const RunOptions& options) {
  return options.sitlnet_exe.substr(0, options.sitlnet_exe.rfind('/'));
}

// What every process started in robot `plan` is told of its place.
images::LaunchContext RobotContext(const Scenario& scenario, const RunOptions& options,
                                   const RobotPlan& plan) {
  images::LaunchContext context;
  context.sitlnet_bin_dir = BinDir(options);
  context.program = options.program;
  context.scenario = scenario.name;
  context.robot = plan.name;
  context.robot_index = plan.index;
  context.physics_address = FormatIpv4(plan.ctl_root_address) + ":" +
                            std::to_string(scenario.spec.addresses().physics_port());
  const proto::GeodeticOrigin& origin = scenario.spec.geodetic_origin();
  char home[96];
  std::snprintf(home, sizeof home, "%.9f,%.9f,%.3f", origin.latitude_deg(),
                origin.longitude_deg(), origin.altitude_m());
  context.geodetic_origin = home;
  return context;
}

// The robot's cgroup with its image's limits, or null (said once per run) when the host offers
// none and the image asks for no limit; throws Error naming the robot for a limit that cannot be
// applied.
std::unique_ptr<nns::RobotCgroup> MakeCgroup(const Scenario& scenario, const std::string& robot,
                                             const images::Image& image, const std::string& program,
                                             bool* warned) {
  const proto::ImageManifest::Limits& limits = image.manifest.limits();
  nns::CgroupLimits cgroup_limits;
  cgroup_limits.memory_max_bytes = static_cast<int64_t>(limits.memory_max_mib()) << 20;
  cgroup_limits.pids_max = limits.pids_max();
  cgroup_limits.cpu_max_cores = limits.cpu_max_cores();
  auto cgroup = std::make_unique<nns::RobotCgroup>(scenario.name, robot, cgroup_limits);
  if (cgroup->unavailable().empty()) return cgroup;
  if (!*warned) {
    std::fprintf(stderr,
                 "%s: warning: the robots run without a cgroup (%s): their CPU time and "
                 "memory are not accounted, and a robot's process that leaves its sandbox's "
                 "namespaces may outlive it (docs/security.md)\n",
                 program.c_str(), cgroup->unavailable().c_str());
    *warned = true;
  }
  return nullptr;
}

}  // namespace

std::vector<RobotSlot> StartImages(const Scenario& scenario, const RunOptions& options,
                                   const std::string& run_dir, const std::vector<int>& only) {
  std::vector<RobotSlot> robots(scenario.robots.size());
  bool warned_no_cgroup = false;
  for (const RobotPlan& plan : scenario.robots) {
    RobotSlot& slot = robots[plan.index];
    slot.name = plan.name;
    if (plan.spec.image().empty()) continue;
    if (!only.empty() && !std::binary_search(only.begin(), only.end(), plan.index)) continue;
    const images::Image image = images::LoadImage(options.images_root, plan.spec.image());
    images::LaunchContext context = RobotContext(scenario, options, plan);
    context.robot_args.assign(plan.spec.args().begin(), plan.spec.args().end());
    context.realtime_factor = scenario.lockstep() ? 0 : scenario.spec.timing().realtime_factor();
    google::protobuf::TextFormat::Printer one_line;
    one_line.SetSingleLineMode(true);
    one_line.PrintToString(plan.airframe, &context.airframe_text);
    images::CheckFiles(image, context);
    if (image.manifest.sandbox() == proto::ImageManifest::NONE) {
      std::fprintf(stderr,
                   "%s: warning: robot \"%s\": image \"%s\" runs without a sandbox "
                   "(sandbox: NONE in %s): it shares the host's files, processes and privileges "
                   "(docs/security.md)\n",
                   options.program.c_str(), plan.name.c_str(), image.manifest.name().c_str(),
                   image.manifest_path.c_str());
    }
    // Recorded before it exists: `down` removes it by name even if this run is killed while
    // podman creates it.
    if (const auto container = images::ContainerTargetOf(image, context)) {
      slot.container = std::make_unique<nns::ContainerRegistration>(
          scenario.name, container->engine_exe, container->name);
    } else {
      slot.cgroup = MakeCgroup(scenario, plan.name, image, options.program, &warned_no_cgroup);
      if (slot.cgroup) context.cgroup_join_fds = slot.cgroup->join_fds();
    }
    slot.process = std::make_unique<images::RobotProcess>(
        image, context, options.sitlnet_exe, run_dir + "/robots/" + plan.name + ".log");
    slot.image = image;
    slot.context = context;
    slot.sitlnet_exe = options.sitlnet_exe;
    slot.started_wall_ns = MonotonicNowNs();
  }
  // A program that is missing or dies at once shows within a moment; this
  // bounded wait is the start-up check, not a synchronization.
  // One 300 ms window for the whole fleet, not 300 ms per robot (64 robots
  // took 19 s to start with per-robot waits).
  const TimeNs check_until_ns = MonotonicNowNs() + 300 * kNsPerMs;
  for (RobotSlot& slot : robots) {
    if (!slot.process) continue;
    const TimeNs left_ns = std::max<TimeNs>(0, check_until_ns - MonotonicNowNs());
    if (const auto status = slot.process->WaitExit(left_ns); status && *status != 0) {
      throw Error("robot \"" + slot.name + "\": its image exited at once with status " +
                  std::to_string(*status) +
                  run_formats::LogSays(run_formats::FirstErrorLine(
                      run_formats::ReadLogTail(slot.process->log_path()))) +
                  "; see " + slot.process->log_path());
    }
  }
  return robots;
}

std::vector<std::unique_ptr<images::RobotProcess>> StartClockPublishers(
    const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
    const ros2_clock::SharedVirtualTime& shared) {
  std::vector<std::unique_ptr<images::RobotProcess>> publishers;
  const proto::Timing& timing = scenario.spec.timing();
  if (timing.ros2_clock_hz() == 0) return publishers;
  const std::string bin_dir = BinDir(options);
  const bool lockstep = scenario.lockstep();
  // The shared time moves once per iteration: polling twice per iteration's wall time is
  // enough in realtime; in lockstep an iteration's wall time is not known, 1 ms it is.
  const int64_t poll_us =
      lockstep
          ? 1000
          : std::max<int64_t>(
                100, static_cast<int64_t>(timing.iteration_us() / timing.realtime_factor() / 2));
  images::Image image;
  image.dir = bin_dir;
  image.manifest_path = "(built in: timing.ros2_clock_hz)";
  image.manifest.set_name("ros2_clock");
  for (const std::string& arg : {bin_dir + "/ros2_clock_publisher", std::string("--time-fd"),
                                 std::to_string(images::kPassedFd), std::string("--rate-hz"),
                                 std::to_string(timing.ros2_clock_hz()), std::string("--poll-us"),
                                 std::to_string(poll_us)}) {
    image.manifest.add_command(arg);
  }
  image.manifest.add_files(bin_dir + "/ros2_clock_publisher");
  image.manifest.set_time(proto::ImageManifest::WALL);
  image.manifest.set_ready_log_line("ros2_clock_publisher: /clock");
  for (const RobotPlan& plan : scenario.robots) {
    images::LaunchContext context = RobotContext(scenario, options, plan);
    context.passed_fd = shared.fd();
    images::CheckFiles(image, context);
    publishers.push_back(std::make_unique<images::RobotProcess>(
        image, context, options.sitlnet_exe, run_dir + "/robots/" + plan.name + ".ros2_clock.log"));
  }
  return publishers;
}

namespace {

// The start bound: the scenario's, else 10 s plus each booting robot's image's boot cost.
TimeNs StartBoundNs(const Scenario& scenario, const std::vector<RobotSlot>& robots) {
  const proto::Timing& timing = scenario.spec.timing();
  if (timing.has_start_timeout_ms()) return timing.start_timeout_ms() * kNsPerMs;
  TimeNs bound_ns = 10 * kNsPerS;
  for (const RobotSlot& robot : robots) {
    if (robot.process) bound_ns += robot.image.manifest.boot_cost_ms() * kNsPerMs;
  }
  return bound_ns;
}

// The CPUs this process (and the robots it starts) may run on.
int UsableCpuCount() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return 1;
  return std::max(1, CPU_COUNT(&set));
}

BootSample SampleBoot(const RobotSlot& robot) {
  BootSample sample;
  struct stat log {};
  if (stat(robot.process->log_path().c_str(), &log) == 0) sample.log_bytes = log.st_size;
  if (robot.cgroup) sample.cpu_ns = robot.cgroup->Usage().cpu_ns;
  return sample;
}

}  // namespace

void WaitForRobotsToSpeak(const Scenario& scenario, std::vector<RobotSlot>& robots,
                          physics::PhysicsServer* server, const std::string& why) {
  const TimeNs bound_ns = StartBoundNs(scenario, robots);
  const TimeNs start_ns = MonotonicNowNs();
  const TimeNs deadline = start_ns + bound_ns;
  BootProgress progress(static_cast<int>(robots.size()), UsableCpuCount(), start_ns);
  TimeNs next_sample_ns = start_ns;
  for (;;) {
    server->Poll();
    const TimeNs now = MonotonicNowNs();
    std::vector<int> silent;
    for (const RobotPlan& plan : scenario.robots) {
      RobotSlot& robot = robots[plan.index];
      // A ground station's software has no physics to speak to.
      if (robot.process && !plan.spec.ground_station() && !server->spoke(plan.index)) {
        if (const std::optional<int> status = robot.process->PollExit()) {
          throw Error(why + ": robot \"" + plan.name + "\" exited (status " +
                      std::to_string(*status) + ") before it spoke to physics" +
                      run_formats::LogSays(run_formats::FirstErrorLine(
                          run_formats::ReadLogTail(robot.process->log_path()))) +
                      " (log: " + robot.process->log_path() + ")");
        }
        silent.push_back(plan.index);
      }
    }
    if (silent.empty()) return;
    std::vector<int> still;  // Silent and still for the stall window: named before the bound.
    // Sampled once a second, not at every packet that wakes the wait (a log's stat and a cgroup
    // file per silent robot).
    const bool sample = now >= next_sample_ns;
    if (sample) next_sample_ns = now + kNsPerS;
    for (int index : silent) {
      if (sample) {
        progress.Observe(index, SampleBoot(robots[index]), static_cast<int>(silent.size()), now);
      }
      if (progress.StillForNs(index, now) >= kBootStallNs) still.push_back(index);
    }
    if (!still.empty() || now >= deadline) {
      const std::vector<int>& named = still.empty() ? silent : still;
      std::string names;
      for (int index : named) names += (names.empty() ? "" : ", ") + robots[index].name;
      const std::string last =
          run_formats::LastLine(run_formats::ReadLogTail(robots[named[0]].process->log_path()));
      throw Error(why + ": robots " + names +
                  " sent no MotorCommand (nor servo frame, nor PX4 connection) " +
                  (still.empty() ? "within the start bound, " + std::to_string(bound_ns / kNsPerMs) +
                                       " ms (timing.start_timeout_ms)"
                                 : "and made no progress (log and CPU time still) for " +
                                       std::to_string(kBootStallNs / kNsPerMs) + " ms") +
                  (last.empty() ? "" : "; " + robots[named[0]].name + "'s log ends \"" + last + "\"") +
                  " (see their logs in robots/)");
    }
    // Woken by the physics server or by a silent image that exits (named at once, not at the
    // deadline: a PX4 that exits at boot may take a second or more on a busy host); and each
    // second, to look at the booting robots' progress.
    std::vector<pollfd> wait = {{server->wait_fd(), POLLIN, 0}};
    for (int index : silent) {
      const int exit_fd = robots[index].process->exit_fd();
      if (exit_fd >= 0) wait.push_back({exit_fd, POLLIN, 0});
    }
    const TimeNs sleep_ns = std::min<TimeNs>(deadline - now, kNsPerS);
    poll(wait.data(), wait.size(), static_cast<int>(sleep_ns / kNsPerMs) + 1);
  }
}

}  // namespace sitlnet::runner
