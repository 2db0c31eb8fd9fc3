// `sitlnet run`: the whole pipeline for one scenario, as a script.
#include <google/protobuf/text_format.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <fstream>
#include <memory>
#include <optional>

#include "coordinator/coordinator.h"
#include "network_side/network_side.h"
#include "nns/nns.h"
#include "physics_side/physics_side.h"
#include "runner/outputs.h"
#include "runner/run_folder.h"
#include "runner/run_monitor.h"
#include "runner/runner.h"
#include "runner/summary.h"

namespace sitlnet::runner {
namespace {

Scenario LoadWithOverrides(const RunOptions& options) {
  return ApplyRunOverrides(LoadScenarioFile(options.scenario_path), options);
}

std::string DefaultRunDir(const std::string& scenario_name) {
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  return "runs/" + scenario_name + "-" + stamp;
}

// Tears the scenario down however the run ends.
class DownOnExit {
 public:
  explicit DownOnExit(std::string name) : name_(std::move(name)) {}
  ~DownOnExit() {
    try {
      nns::Down(name_);
    } catch (const std::exception& error) {
      std::fprintf(stderr, "sitlnet run: down %s: %s\n", name_.c_str(), error.what());
    }
  }

 private:
  std::string name_;
};

// Starts every robot's image; throws Error naming the robot and its log if
// one cannot start or exits at once.
// Folder of the sitlnet binary (${SITLNET_BIN}; the flocker and ros2_clock programs are there).
std::string BinDir(const RunOptions& options) {
  return options.sitlnet_exe.substr(0, options.sitlnet_exe.rfind('/'));
}

// What every process started in robot `plan` is told of its place.
images::LaunchContext RobotContext(const Scenario& scenario, const RunOptions& options,
                                   const RobotPlan& plan) {
  images::LaunchContext context;
  context.sitlnet_bin_dir = BinDir(options);
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
                                             const images::Image& image, bool* warned) {
  const proto::ImageManifest::Limits& limits = image.manifest.limits();
  nns::CgroupLimits cgroup_limits;
  cgroup_limits.memory_max_bytes = static_cast<int64_t>(limits.memory_max_mib()) << 20;
  cgroup_limits.pids_max = limits.pids_max();
  cgroup_limits.cpu_max_cores = limits.cpu_max_cores();
  auto cgroup = std::make_unique<nns::RobotCgroup>(scenario.name, robot, cgroup_limits);
  if (cgroup->unavailable().empty()) return cgroup;
  if (!*warned) {
    std::fprintf(stderr,
                 "sitlnet run: warning: the robots run without a cgroup (%s): their CPU time and "
                 "memory are not accounted, and a robot's process that leaves its sandbox's "
                 "namespaces may outlive it (docs/security.md)\n",
                 cgroup->unavailable().c_str());
    *warned = true;
  }
  return nullptr;
}

std::vector<RobotSlot> StartImages(const Scenario& scenario, const RunOptions& options,
                                   const std::string& run_dir) {
  std::vector<RobotSlot> robots(scenario.robots.size());
  bool warned_no_cgroup = false;
  for (const RobotPlan& plan : scenario.robots) {
    RobotSlot& slot = robots[plan.index];
    slot.name = plan.name;
    if (plan.spec.image().empty()) continue;
    const images::Image image = images::LoadImage(options.images_root, plan.spec.image());
    images::LaunchContext context = RobotContext(scenario, options, plan);
    context.robot_args.assign(plan.spec.args().begin(), plan.spec.args().end());
    context.realtime_factor = scenario.spec.timing().pacing() == proto::Timing::PACING_LOCKSTEP
                                  ? 0
                                  : scenario.spec.timing().realtime_factor();
    google::protobuf::TextFormat::Printer one_line;
    one_line.SetSingleLineMode(true);
    one_line.PrintToString(plan.airframe, &context.airframe_text);
    images::CheckFiles(image, context);
    if (image.manifest.sandbox() == proto::ImageManifest::NONE) {
      std::fprintf(stderr,
                   "sitlnet run: warning: robot \"%s\": image \"%s\" runs without a sandbox "
                   "(sandbox: NONE in %s): it shares the host's files, processes and privileges "
                   "(docs/security.md)\n",
                   plan.name.c_str(), image.manifest.name().c_str(), image.manifest_path.c_str());
    }
    // Recorded before it exists: `down` removes it by name even if this run is killed while
    // podman creates it.
    if (const auto container = images::ContainerTargetOf(image, context)) {
      slot.container = std::make_unique<nns::ContainerRegistration>(
          scenario.name, container->engine_exe, container->name);
    } else {
      slot.cgroup = MakeCgroup(scenario, plan.name, image, &warned_no_cgroup);
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
                  std::to_string(*status) + "; see " + slot.process->log_path());
    }
  }
  return robots;
}

// Timing.ros2_clock_hz > 0: one /clock publisher per robot (ros2_clock/), started like an image
// (sandboxed, in the robot's namespace, log <run>/robots/<robot>.ros2_clock.log) and handed the
// run's shared virtual time as descriptor images::kPassedFd.
std::vector<std::unique_ptr<images::RobotProcess>> StartClockPublishers(
    const Scenario& scenario, const RunOptions& options, const std::string& run_dir,
    const ros2_clock::SharedVirtualTime& shared) {
  std::vector<std::unique_ptr<images::RobotProcess>> publishers;
  const proto::Timing& timing = scenario.spec.timing();
  if (timing.ros2_clock_hz() == 0) return publishers;
  const std::string bin_dir = BinDir(options);
  const bool lockstep = timing.pacing() == proto::Timing::PACING_LOCKSTEP;
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

// Lockstep: every robot with an image must have announced itself (a first
// MotorCommand) before iteration 0, so that all of them take part from the
// first step and two runs start alike. Waits on the server's socket, at most
// 10 s of wall time plus 250 ms per robot with an image: 64 container images took 9.7 s to
// start on a loaded 2-core host (docs/performance.md, "Containers").
// `why`: what makes the run wait ("lockstep", "wait_for_robots"), the error's first word.
// An image that exits meanwhile ends the wait at once, named with its status (restart policies
// apply once the run has begun).
void WaitForRobotsToSpeak(const Scenario& scenario, std::vector<RobotSlot>& robots,
                          physics::PhysicsServer* server, const std::string& why) {
  const TimeNs allowed_ns =
      10 * kNsPerS + 250 * kNsPerMs *
                         std::count_if(robots.begin(), robots.end(),
                                       [](const RobotSlot& r) { return r.process != nullptr; });
  const TimeNs deadline = MonotonicNowNs() + allowed_ns;
  for (;;) {
    server->Poll();
    std::string silent;
    for (const RobotPlan& plan : scenario.robots) {
      RobotSlot& robot = robots[plan.index];
      // A ground station's software has no physics to speak to.
      if (robot.process && !plan.spec.ground_station() && !server->spoke(plan.index)) {
        if (const std::optional<int> status = robot.process->PollExit()) {
          throw Error(why + ": robot \"" + plan.name + "\" exited (status " +
                      std::to_string(*status) +
                      ") before it spoke to physics (log: " + robot.process->log_path() + ")");
        }
        silent += (silent.empty() ? "" : ", ") + plan.name;
      }
    }
    if (silent.empty()) return;
    const TimeNs now = MonotonicNowNs();
    if (now >= deadline) {
      throw Error(why + ": robots " + silent +
                  " sent no MotorCommand (nor servo frame, nor PX4 connection) within " +
                  std::to_string(allowed_ns / kNsPerMs) +
                  " ms of starting (see their logs in robots/)");
    }
    pollfd wait{server->wait_fd(), POLLIN, 0};
    poll(&wait, 1, static_cast<int>((deadline - now) / kNsPerMs) + 1);
  }
}

// VmHWM of a process in KiB (0 if unreadable): its peak resident set since exec.
int64_t PeakRssKib(pid_t pid) {
  std::ifstream status("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmHWM:", 0) == 0) return std::atoll(line.c_str() + 6);
  }
  return 0;
}

// Benchmark knobs (bench/scale, docs/performance.md), not scenario settings:
// SITLNET_PHYSICS_THREADS=N steps the robots on N threads (default 2) and
// SITLNET_PHYSICS_INTEGRATOR=euler|rk4 overrides the scenario's
// timing.physics_integrator (Euler trades RK4's accuracy, docs/physics.md, for about a
// third of its cost). Anything else is a one-line error.
physics::ServerOptions PhysicsOptionsFromEnvironment() {
  physics::ServerOptions options;
  if (const char* threads = std::getenv("SITLNET_PHYSICS_THREADS"); threads && *threads) {
    char* end = nullptr;
    const long value = std::strtol(threads, &end, 10);
    if (*end != '\0' || value < 1 || value > 64) {
      throw Error(std::string("SITLNET_PHYSICS_THREADS=\"") + threads + "\": want 1..64");
    }
    options.world.threads = static_cast<int>(value);
  }
  if (const char* integrator = std::getenv("SITLNET_PHYSICS_INTEGRATOR");
      integrator && *integrator) {
    const std::string name = integrator;
    if (name != "euler" && name != "rk4") {
      throw Error("SITLNET_PHYSICS_INTEGRATOR=\"" + name + "\": want euler or rk4");
    }
    options.world.integrator =
        name == "euler" ? physics::Integrator::kEuler : physics::Integrator::kRk4;
  }
  // SITLNET_PHYSICS_CULL_TILE_M=M: obstacle tiles of M metres; 0: no culling (docs/physics.md).
  if (const char* tile = std::getenv("SITLNET_PHYSICS_CULL_TILE_M"); tile && *tile) {
    char* end = nullptr;
    const double value = std::strtod(tile, &end);
    // 0 or at least a metre: a tile index is the position over the tile size, as an int64.
    if (*end != '\0' || !(value == 0 || (value >= 1 && value <= 1e6))) {
      throw Error(std::string("SITLNET_PHYSICS_CULL_TILE_M=\"") + tile +
                  "\": want 0 (no culling) or 1..1e6 m");
    }
    options.world.cull_obstacles = value > 0;
    if (value > 0) options.world.cull_tile_m = value;
  }
  return options;
}

// `--listen ... --remote network`: waits for the medium's network connector
// (another host's `sitlnet medium FILE --connect`) before anything is
// created, so that a timeout or a refusal leaves nothing behind. Returns null
// if interrupted; throws Error naming the missing side or the refusal.
std::unique_ptr<coordinator::Connector> AcceptRemoteNetwork(const Scenario& scenario,
                                                            const RunOptions& options,
                                                            int interrupt_fd) {
  const coordinator::Endpoint endpoint = coordinator::ParseEndpoint(options.listen);
  if (options.secret_file.empty() && !coordinator::IsLocalOnly(endpoint)) {
    throw Error("--listen " + options.listen +
                " can be reached from other hosts: give --secret-file PATH, the same file as "
                "`sitlnet medium --connect`'s (docs/coordinator.md, \"Authentication\")");
  }
  const std::string secret = options.secret_file.empty()
                                 ? std::string()
                                 : coordinator::LoadSecretFile(options.secret_file);
  coordinator::Listener listener(endpoint);
  std::fprintf(stderr,
               "sitlnet run: %s: waiting %lld s for the network connector on %s "
               "(sitlnet medium FILE --connect HOST:PORT)\n",
               scenario.name.c_str(), static_cast<long long>(options.remote_wait_ns / kNsPerS),
               listener.endpoint().ToString().c_str());
  coordinator::HandshakeExpectation expect;
  expect.scenario_hash = network_side::MediumScenarioHash(scenario);
  expect.iteration_ns = scenario.iteration_ns;
  expect.secret = secret;
  coordinator::WaitLimits limits;
  limits.timeout_ns = options.remote_wait_ns;
  limits.deadline_ns = MonotonicNowNs() + options.remote_wait_ns;
  limits.interrupt_fd = interrupt_fd;
  auto connector =
      coordinator::AcceptConnectorOfRole(listener, coordinator::Role::kNetwork, expect, limits);
  if (connector) std::fprintf(stderr, "sitlnet run: %s connected\n", connector->Describe().c_str());
  return connector;  // The listener closes: nothing else can connect.
}

}  // namespace

// The scenario with the command line's overrides applied, revalidated.
Scenario ApplyRunOverrides(const Scenario& scenario, const RunOptions& options) {
  proto::Scenario spec = scenario.spec;
  if (options.duration_s) {
    if (!(*options.duration_s > 0 && *options.duration_s <= kMaxDurationMs / 1000)) {
      throw Error("--duration must be in (0, " + std::to_string(kMaxDurationMs / 1000) +
                  "] seconds (a year)");
    }
    spec.mutable_timing()->set_duration_ms(static_cast<int64_t>(*options.duration_s * 1000));
  }
  if (options.lockstep) {
    spec.mutable_timing()->set_pacing(*options.lockstep ? proto::Timing::PACING_LOCKSTEP
                                                        : proto::Timing::PACING_REALTIME);
  }
  if (options.seed) spec.mutable_timing()->set_seed(*options.seed);
  if (options.no_shadowing) spec.mutable_radio()->set_shadowing(false);
  std::string text;
  google::protobuf::TextFormat::PrintToString(spec, &text);
  Scenario effective = LoadScenarioText(text, scenario.source_path + " (with overrides)");
  effective.source_path = scenario.source_path;
  return effective;
}

RunReport RunScenario(const RunOptions& options) {
  const TimeNs begin_ns = MonotonicNowNs();
  const Scenario scenario = LoadWithOverrides(options);
  RunReport report;
  report.run_dir = options.out_dir.empty() ? DefaultRunDir(scenario.name) : options.out_dir;
  if (!options.listen.empty() &&
      scenario.spec.timing().pacing() != proto::Timing::PACING_LOCKSTEP) {
    throw Error(
        "--remote network needs lockstep pacing (--pacing lockstep): in realtime the bridge "
        "asks its medium for the next event at every frame, a network round trip each");
  }
  nns::RequirePrivileges();
  nns::RefuseIfInUse(scenario.name);  // Before the run folder: a refused run leaves nothing.
  // A sandboxed robot's init outlives bubblewrap by a moment (docs/security.md); as the
  // subreaper, this process reaps it, so its CPU time (the image's) is in RUSAGE_CHILDREN.
  prctl(PR_SET_CHILD_SUBREAPER, 1);
  // Per robot: its TAP, physics socket, log, pidfds and the medium's and bridge's own; 64 for
  // the rest (outputs, sockets, pipes). Debian's default soft limit (1024) ran out near 250.
  constexpr uint64_t kOpenFilesPerRobot = 8;
  constexpr uint64_t kOpenFilesBase = 64;
  RaiseOpenFileLimit(kOpenFilesBase + kOpenFilesPerRobot * scenario.robots.size(),
                     "a run of " + std::to_string(scenario.robots.size()) + " robots");
  coordinator::StopSignal stop;  // Ctrl-C from here on stops in order.
  MakeRunFolder(report.run_dir);
  {
    std::string text;
    google::protobuf::TextFormat::PrintToString(scenario.spec, &text);
    LineFile(report.run_dir + "/scenario.textproto",
             "# Effective scenario of this run (from " + scenario.source_path + ")", 1,
             "effective scenario")
        .AppendRecord(text);
  }

  // Wrapped at once, so that whatever fails from here on, the remote side
  // gets Stop with a reason rather than a closed connection.
  std::unique_ptr<network_side::RemoteMedium> remote_owned;  // Until the bridge takes it.
  if (!options.listen.empty()) {
    std::unique_ptr<coordinator::Connector> connector;
    try {
      connector = AcceptRemoteNetwork(scenario, options, stop.fd());
    } catch (const Error& error) {
      std::fprintf(stderr, "sitlnet run: %s\n", error.what());
      report.exit_code = 1;
      return report;
    }
    if (!connector) {
      report.interrupted = true;
      report.exit_code = 130;
      return report;
    }
    remote_owned = std::make_unique<network_side::RemoteMedium>(
        scenario, std::move(connector), coordinator::CoordinatorOptions{}.answer_timeout_ns);
  }

  nns::UpOptions up_options;
  up_options.register_caller_as_run = true;  // Another run of it is refused, not torn down.
  nns::Up(scenario, up_options);
  DownOnExit down(scenario.name);
  std::fprintf(stderr,
               "sitlnet run: %s: %zu robots up, starting medium, physics and images -> %s\n",
               scenario.name.c_str(), scenario.robots.size(), report.run_dir.c_str());
  const bool lockstep = scenario.spec.timing().pacing() == proto::Timing::PACING_LOCKSTEP;
  // Realtime pacing on a busy host: a normal-priority loop waits milliseconds for a core
  // (docs/performance.md, "Realtime 64"). Before the physics and bridge threads exist, so that
  // they inherit it; children (images, gnuplot) reset to normal scheduling.
  if (!lockstep && options.realtime_priority > 0) {
    if (const std::string refused = RequestRealtimePriority(options.realtime_priority);
        !refused.empty()) {
      std::fprintf(stderr, "sitlnet run: warning: %s\n", refused.c_str());
    }
  }

  // Its sockets in the scenario's ctl namespace, where the robots' ctl0 links end: no one else
  // can bind their ports there (nns.h, CtlNetnsName).
  physics::ServerOptions physics_options = PhysicsOptionsFromEnvironment();
  physics_options.make_sockets = nns::InNetns(nns::CtlNetnsName(scenario.name));
  // The autopilots' pacing: in lockstep the frame gate (silent after the scenario's timeout),
  // in realtime the run's timebase (the coordinator begins it before iteration 0).
  clock::Timebase run_timebase(scenario.spec.timing().realtime_factor());
  const TimeNs silent_robot_timeout_ns = scenario.spec.silent_robot_timeout_ms() * kNsPerMs;
  if (lockstep) {
    physics_options.periodic_states = false;  // one state per iteration, from the gate
    physics_options.frame_gate_timeout_ns = silent_robot_timeout_ns;
  } else {
    physics_options.autopilot_wall_clock = &run_timebase;
  }
  physics::PhysicsServer physics_server(scenario, physics_options);
  tapbridge::BridgeOptions bridge_options;
  bridge_options.seed = scenario.spec.timing().seed();
  network_side::RemoteMedium* remote_medium = nullptr;  // Owned by the bridge.
  std::unique_ptr<tapbridge::MediumModel> medium;
  if (remote_owned) {
    remote_medium = remote_owned.get();
    medium = std::move(remote_owned);
  } else {
    medium = tapbridge::MakeMacPhySimMedium(scenario);
  }
  tapbridge::BridgeCore bridge(scenario, std::move(medium), bridge_options);
  bridge.AttachAll();

  // The medium's view: pcap (virtual timestamps in lockstep, so that runs
  // are byte-identical; wall-clock dates in realtime) and the delivery log.
  LineFile pcap(report.run_dir + "/medium.pcap", "", 256, "pcap");
  pcap.AppendRecord(tapbridge::PcapFileHeader());
  const TimeNs epoch_offset_ns = lockstep ? 0 : static_cast<TimeNs>(std::time(nullptr)) * kNsPerS;
  bridge.AddAirFrameObserver([&](const tapbridge::AirFrame& frame) {
    pcap.AppendRecord(tapbridge::EncodePcapRecord(frame, epoch_offset_ns));
  });
  LineFile deliveries(report.run_dir + "/deliveries.csv", kDeliveryHeader);
  // The communication graph over time (connectivity.csv), fed as deliveries happen.
  ConnectivityTracker connectivity(static_cast<int>(scenario.robots.size()), kConnectivityWindowNs,
                                   kConnectivitySampleNs);
  bridge.AddDeliveryObserver([&](const tapbridge::Delivery& d) {
    connectivity.Heard(d.delivery_ns, d.source, d.station);
    char line[128];
    std::snprintf(line, sizeof line, "%lld,%d,%d,%.2f,%.2f", static_cast<long long>(d.delivery_ns),
                  d.source, d.station, d.rx_power_dbm, d.sinr_db);
    deliveries.Append(line);
  });

  std::vector<RobotSlot> robots = StartImages(scenario, options, report.run_dir);
  std::optional<ros2_clock::SharedVirtualTime> shared_time;
  if (scenario.spec.timing().ros2_clock_hz() > 0) {
    shared_time.emplace(ros2_clock::SharedVirtualTime::Create());
  }
  std::vector<std::unique_ptr<images::RobotProcess>> clock_publishers =
      shared_time ? StartClockPublishers(scenario, options, report.run_dir, *shared_time)
                  : std::vector<std::unique_ptr<images::RobotProcess>>{};

  physics_side::RobotLockstepOptions robot_lockstep;
  robot_lockstep.enabled = lockstep;
  robot_lockstep.command_timeout_ns = silent_robot_timeout_ns;
  robot_lockstep.drop_silent =
      scenario.spec.on_silent_robot() == proto::Scenario::SILENT_ROBOT_DROP;
  // Realtime with wait_for_robots too: the clock starts once the images have booted
  // (docs/performance.md, "Where the realtime bursts come from").
  if (lockstep || scenario.spec.timing().wait_for_robots()) {
    WaitForRobotsToSpeak(scenario, robots, &physics_server,
                         lockstep ? "lockstep" : "wait_for_robots");
    // Readiness is timed from the clock's start: an image that spoke early may have waited
    // for the slowest one longer than its ready_timeout_ms.
    for (RobotSlot& robot : robots) robot.started_wall_ns = MonotonicNowNs();
  }
  physics_side::PhysicsServerSimulator physics_sim(scenario, &physics_server, robot_lockstep);
  RecordingPhysics recording(&physics_sim, &physics_server.world(),
                             physics::GeodeticFrame(scenario.spec.geodetic_origin()),
                             report.run_dir + "/trajectories.csv", options.trajectory_period_ns);
  if (shared_time) recording.ShareTimeWith(&*shared_time);
  network_side::BridgeSimulator bridge_sim(
      scenario, &bridge, lockstep ? coordinator::Pacing::kLockstep : coordinator::Pacing::kRealtime,
      scenario.spec.timing().realtime_factor());
  MonitoringNetwork monitoring(
      &bridge_sim, &bridge, &robots,
      scenario.spec.on_robot_failure() == proto::Scenario::ROBOT_FAILURE_STOP, options.progress,
      scenario.duration_ns);
  auto physics = coordinator::MakeInProcessConnector(
      "physics", coordinator::Role::kPhysics, &recording, coordinator::Threading::kOwnThread);
  // The bridge is single-threaded: always the coordinator's own thread.
  auto network = coordinator::MakeInProcessConnector(
      "network", coordinator::Role::kNetwork, &monitoring, coordinator::Threading::kCallerThread);

  coordinator::CoordinatorOptions run_options = coordinator::OptionsFromScenario(scenario);
  run_options.timebase_out = &run_timebase;
  coordinator::MetricsCsvWriter metrics_csv(report.run_dir + "/metrics.csv");
  coordinator::MetricsCollector metrics;
  run_options.metrics_csv = &metrics_csv;
  run_options.metrics = &metrics;
  run_options.interrupt_fd = stop.fd();
  run_options.lockstep_robots = lockstep;
  std::string failure;
  coordinator::RunResult result;
  const TimeNs loop_begin_ns = MonotonicNowNs();
  report.startup_ns = loop_begin_ns - begin_ns;
  try {
    result = coordinator::RunCoordinator(*physics, *network, run_options);
  } catch (const Error& error) {
    failure = error.what();
  }
  const TimeNs loop_end_ns = MonotonicNowNs();
  report.loop_ns = loop_end_ns - loop_begin_ns;
  const auto cpu_s = [](const rusage& usage) {
    return static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
           static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec) / 1e6;
  };
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  report.self_cpu_s = cpu_s(usage);
  monitoring.FinishProgress();
  metrics_csv.Flush();
  recording.Flush();
  // SIGTERM to every image first, then wait for each: images may need up to
  // their receive timeout to notice (flocker: 1 s), so stopping them one
  // after the other took 41 s for 64 robots.
  std::vector<int64_t> rss_kib;
  for (RobotSlot& robot : robots) {
    if (robot.process && !robot.exit_status && !robot.process->PollExit()) {
      const int64_t peak = PeakRssKib(robot.process->CommandPid());
      if (peak > 0) rss_kib.push_back(peak);
      robot.process->RequestStop();
    }
  }
  if (!rss_kib.empty()) {
    std::sort(rss_kib.begin(), rss_kib.end());
    report.robot_max_rss_kib = rss_kib.back();
    report.robot_median_rss_kib = rss_kib[rss_kib.size() / 2];
  }
  for (RobotSlot& robot : robots) {
    if (robot.process && !robot.exit_status) robot.process->Stop();
    // Whatever the robot left behind (a process that left its session or namespaces) is in its
    // cgroup: killed, then what all of them used is read.
    if (robot.cgroup) {
      robot.cgroup->KillAll();
      robot.usage = robot.cgroup->Usage();
    }
  }
  for (auto& publisher : clock_publishers) publisher->RequestStop();
  clock_publishers.clear();  // Stop() each: it ends at SIGTERM.
  report.stop_ns = MonotonicNowNs() - loop_end_ns;
  // Every image is reaped by now and nothing else was a child yet (gnuplot
  // runs later), so the children's usage is the robots'.
  getrusage(RUSAGE_CHILDREN, &usage);
  report.robots_cpu_s = cpu_s(usage);
  deliveries.Flush();
  pcap.Flush();

  report.interrupted = result.interrupted;
  report.exit_code = !failure.empty() ? 1 : result.interrupted ? 130 : 0;
  if (!failure.empty()) std::fprintf(stderr, "sitlnet run: %s\n", failure.c_str());
  if (remote_medium) {
    const network_side::MediumLinkStats& link = remote_medium->stats();
    report.medium_link = link;
    const network_side::MediumLinkStats::Means mean = link.PerRoundTrip();
    std::fprintf(stderr,
                 "sitlnet run: medium link to %s: %lld round trips (%lld quiet steps without), "
                 "mean %.1f us each (remote medium %.1f us, transport %.1f us), %.0f B out, "
                 "%.0f B back\n",
                 remote_medium->Describe().c_str(), static_cast<long long>(link.round_trips),
                 static_cast<long long>(link.quiet_steps), mean.round_trip_us,
                 mean.remote_medium_us, mean.transport_us, mean.request_bytes, mean.reply_bytes);
  }
  // A failed run throws out of RunCoordinator before it returns a count: the
  // metrics have one row per iteration done.
  const coordinator::MetricsSummary summary = metrics.Summarize();
  WriteSummaryAndPlots(scenario, report, summary,
                       std::max<int64_t>(result.iterations_done, summary.iterations), robots,
                       bridge, physics_server, &connectivity, failure);
  if (remote_medium) {
    remote_medium->Stop(failure.empty() ? (result.interrupted ? "interrupted" : "run finished")
                                        : failure);
  }
  return report;
}

}  // namespace sitlnet::runner
