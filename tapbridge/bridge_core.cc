// BridgeCore: the robots' ports <-> medium, with the realtime and lockstep drivers.
// Realtime: every frame is stamped with the virtual time of the instant it
// was read; the medium is advanced to "now" after every batch of wakeups, and
// a timerfd armed on the absolute wall instant of the medium's next event
// (TFD_TIMER_ABSTIME, 1 ns timer slack) wakes the loop exactly then, so a
// delivery is written when it is due, not at a step boundary.
#include <sys/epoll.h>
#include <sys/prctl.h>
#include <sys/timerfd.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include "tapbridge/lateness_histogram.h"
#include "tapbridge/lockstep_spread.h"
#include "tapbridge/tap_port.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

constexpr size_t kReadBufferBytes = 65536 + 64;  // Largest TAP frame (64 KB MTU) fits.

}  // namespace

struct BridgeCore::Impl {
  Scenario scenario;
  std::unique_ptr<MediumModel> medium;
  BridgeOptions options;
  std::vector<std::unique_ptr<Port>> ports;  // Null when not attached.
  std::vector<PortCounters> counters;
  std::vector<bool> warned_unknown_source;
  std::vector<AirFrameObserver> observers;
  std::vector<std::function<void(const Delivery&)>> delivery_observers;
  bool capture_air = true;
  std::vector<uint8_t> buffer = std::vector<uint8_t>(kReadBufferBytes);
  std::vector<Delivery> deliveries;
  std::vector<AirFrame> air;

  // Realtime driver.
  EventLoop* loop = nullptr;
  std::weak_ptr<const void> loop_lifetime;  // Expired: the loop is gone, do not touch it.
  UniqueFd timer_fd;
  clock::Timebase timebase;  // Set by StartRealtime.
  TimeNs armed_wall_ns = -1;
  TimeNs stopped_at_ns = -1;  // Virtual time when StopRealtime ran.
  LatenessHistogram interval_lateness;
  LatenessHistogram total_lateness;

  // Lockstep driver: one generator per robot, derived from the seed.
  TimeNs lockstep_until_ns = 0;
  std::vector<std::mt19937_64> robot_rngs;

  void Log(const std::string& line) const {
    if (options.log) {
      options.log(line);
    } else {
      std::fprintf(stderr, "sitlnet medium: %s\n", line.c_str());
    }
  }

  TimeNs WallOf(TimeNs virtual_ns) const { return timebase.WallOf(virtual_ns); }
  TimeNs VirtualOf(TimeNs wall_ns) const { return timebase.VirtualOf(wall_ns); }

  // Runs the medium to `until_ns` and hands out what it produced.
  void AdvanceMediumTo(TimeNs until_ns) {
    deliveries.clear();
    air.clear();
    medium->AdvanceTo(until_ns, &deliveries, capture_air && !observers.empty() ? &air : nullptr);
    for (const AirFrame& frame : air) {
      for (const AirFrameObserver& observer : observers) observer(frame);
    }
    for (const Delivery& d : deliveries) {
      for (const auto& observer : delivery_observers) observer(d);
      Port* port = ports[d.station].get();
      if (!port) continue;
      PortCounters& c = counters[d.station];
      if (port->Write(d.ethernet_frame) == 0) {
        ++c.frames_written;
      } else {
        ++c.write_errors;
      }
      if (loop) {
        // Measured right after the write(): what a reader in the robot sees.
        const TimeNs lateness_ns = MonotonicNowNs() - WallOf(d.delivery_ns);
        interval_lateness.Add(lateness_ns);
        total_lateness.Add(lateness_ns);
      }
    }
  }

  // Checks one frame read from robot's TAP and enters it into the medium.
  void EnterFrame(int robot, std::span<const uint8_t> frame, TimeNs at_ns) {
    PortCounters& c = counters[robot];
    ++c.frames_read;
    c.bytes_read += frame.size();
    if (frame.size() < 14) {
      ++c.runt_dropped;
      return;
    }
    if (frame.size() > medium->MaxEthernetFrameBytes()) {
      ++c.oversize_dropped;
      return;
    }
    const MacAddress& own = scenario.robots[robot].wlan_mac;
    if (!std::equal(own.bytes.begin(), own.bytes.end(), frame.begin() + 6)) {
      ++c.unknown_source_dropped;
      if (!warned_unknown_source[robot]) {
        warned_unknown_source[robot] = true;
        MacAddress source;
        std::copy(frame.begin() + 6, frame.begin() + 12, source.bytes.begin());
        Log("robot " + scenario.robots[robot].name + ": frame from source MAC " +
            FormatMac(source) + " is not the robot's " + FormatMac(own) +
            "; dropping such frames (counted as unknown_source_dropped)");
      }
      return;
    }
    AdvanceMediumTo(at_ns);
    medium->Submit(robot, at_ns, frame);
  }

  void DrainRealtime(int robot) {
    // epoll is level-triggered: what is left is read on the next wake-up.
    for (size_t turn = 0; turn < kMaxFramesPerRobotPerTurn; ++turn) {
      Port* port = ports[robot].get();
      if (port == nullptr) return;
      const ssize_t n = port->Read(buffer);
      if (n == 0) return;
      if (n < 0) {
        DetachRobot(robot, SystemErrorMessage("read from wlan0 TAP", static_cast<int>(-n)));
        return;
      }
      EnterFrame(robot, std::span<const uint8_t>(buffer.data(), n), VirtualOf(MonotonicNowNs()));
    }
  }

  void ArmTimer() {
    const std::optional<TimeNs> next = medium->NextEventNs();
    // With spinning, wake early by the spin margin and busy-wait the rest.
    const TimeNs wall = next ? WallOf(*next) - options.spin_ns : 0;
    if (wall == armed_wall_ns) return;
    itimerspec spec{};
    if (next) {
      spec.it_value.tv_sec = wall / kNsPerS;
      spec.it_value.tv_nsec = wall % kNsPerS;
      if (wall <= 0) spec.it_value.tv_nsec = 1;  // 0 would disarm.
    }
    timerfd_settime(timer_fd.get(), TFD_TIMER_ABSTIME, &spec, nullptr);
    armed_wall_ns = wall;
  }

  void AfterBatch() {
    AdvanceMediumTo(VirtualOf(MonotonicNowNs()));
    // Optional spin (BridgeOptions::spin_ns): an event due within the margin
    // is waited for on the CPU instead of through a timer wakeup, whose
    // latency (tens of µs on a VM) would otherwise make the delivery late.
    while (options.spin_ns > 0) {
      const std::optional<TimeNs> next = medium->NextEventNs();
      if (!next) break;
      const TimeNs due = WallOf(*next);
      if (due - MonotonicNowNs() > options.spin_ns) break;
      while (MonotonicNowNs() < due) {
        __builtin_ia32_pause();
      }
      AdvanceMediumTo(VirtualOf(MonotonicNowNs()));
    }
    ArmTimer();
  }

  bool AttachRobot(int robot) {
    if (options.open_port) {
      ports[robot] = options.open_port(robot);
      SITLNET_DEMAND(ports[robot] != nullptr);
    } else {
      ports[robot] = std::make_unique<TapPort>(scenario.robots[robot].netns, "wlan0");
    }
    counters[robot].attached = true;
    medium->SetStationEnabled(robot, true);
    if (loop) RegisterPort(robot);
    return true;
  }

  // A port without a descriptor is fed by its owner, not polled (Port::fd).
  void RegisterPort(int robot) {
    if (ports[robot]->fd() < 0) return;
    loop->Add(ports[robot]->fd(), EPOLLIN, [this, robot](uint32_t events) {
      if (events & (EPOLLERR | EPOLLHUP)) {
        DetachRobot(robot, "wlan0 TAP reported an error or hangup");
        return;
      }
      DrainRealtime(robot);
    });
  }

  void DetachRobot(int robot, const std::string& reason) {
    if (!ports[robot]) return;
    if (loop && ports[robot]->fd() >= 0) loop->Remove(ports[robot]->fd());
    ports[robot].reset();
    counters[robot].attached = false;
    medium->SetStationEnabled(robot, false);
    Log("robot " + scenario.robots[robot].name + " (netns " + scenario.robots[robot].netns +
        ") detached: " + reason + "; the other robots keep running");
  }
};

BridgeCore::BridgeCore(const Scenario& scenario, std::unique_ptr<MediumModel> medium,
                       BridgeOptions options)
    : impl_(std::make_unique<Impl>()) {
  SITLNET_DEMAND(medium != nullptr);
  impl_->scenario = scenario;
  impl_->medium = std::move(medium);
  impl_->options = std::move(options);
  const size_t n = scenario.robots.size();
  impl_->ports.resize(n);
  impl_->counters.resize(n);
  impl_->warned_unknown_source.assign(n, false);
  for (size_t i = 0; i < n; ++i) {
    impl_->robot_rngs.push_back(LockstepSpreadStream(impl_->options.seed, i));
  }
}

BridgeCore::~BridgeCore() { StopRealtime(); }

void BridgeCore::AttachAll() {
  const size_t n = impl_->scenario.robots.size();
  for (size_t i = 0; i < n; ++i) {
    if (!impl_->options.robots.empty() &&
        std::find(impl_->options.robots.begin(), impl_->options.robots.end(),
                  static_cast<int>(i)) == impl_->options.robots.end()) {
      impl_->medium->SetStationEnabled(static_cast<int>(i), false);
      continue;
    }
    try {
      impl_->AttachRobot(static_cast<int>(i));
    } catch (const Error& e) {
      const bool busy = std::string(e.what()).find("busy") != std::string::npos;
      throw Error("robot " + impl_->scenario.robots[i].name + ": " + e.what() +
                  (busy ? " (another process holds this TAP: a medium daemon or sitlnet run?)"
                        : " (is the scenario up? sitlnet up " + impl_->scenario.source_path + ")"));
    }
  }
}

bool BridgeCore::Reattach(int robot) {
  if (impl_->ports[robot]) return true;
  try {
    impl_->AttachRobot(robot);
  } catch (const Error&) {
    return false;
  }
  impl_->Log("robot " + impl_->scenario.robots[robot].name + ": re-attached to wlan0 in netns " +
             impl_->scenario.robots[robot].netns);
  return true;
}

void BridgeCore::AddDeliveryObserver(std::function<void(const Delivery&)> observer) {
  impl_->delivery_observers.push_back(std::move(observer));
}

void BridgeCore::AddAirFrameObserver(AirFrameObserver observer) {
  impl_->observers.push_back(std::move(observer));
}

void BridgeCore::SetAirFrameCapture(bool enabled) { impl_->capture_air = enabled; }

void BridgeCore::StartRealtime(EventLoop* loop, const clock::Timebase& timebase) {
  SITLNET_DEMAND(impl_->loop == nullptr);
  // Timer slack defaults to 50 µs for normal threads; deliveries are due to
  // the nanosecond, so ask for the minimum (prctl(2), PR_SET_TIMERSLACK).
  prctl(PR_SET_TIMERSLACK, 1UL, 0, 0, 0);
  impl_->loop = loop;
  impl_->loop_lifetime = loop->lifetime();
  impl_->timebase = timebase;
  impl_->timer_fd.Reset(timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC));
  if (!impl_->timer_fd.valid()) throw Error(SystemErrorMessage("timerfd_create", errno));
  loop->Add(impl_->timer_fd.get(), EPOLLIN, [this](uint32_t) {
    uint64_t expirations = 0;
    [[maybe_unused]] ssize_t n = read(impl_->timer_fd.get(), &expirations, sizeof expirations);
    impl_->armed_wall_ns = -1;  // Fired: re-arm even for the same instant.
  });
  for (size_t i = 0; i < impl_->ports.size(); ++i) {
    if (impl_->ports[i]) impl_->RegisterPort(static_cast<int>(i));
  }
  loop->SetAfterBatch([this] { impl_->AfterBatch(); });
  impl_->AfterBatch();
}

void BridgeCore::StopRealtime() {
  Impl& impl = *impl_;
  if (impl.loop == nullptr) return;
  impl.stopped_at_ns = impl.VirtualOf(MonotonicNowNs());
  // The loop may already be destroyed (a caller that declared it after the
  // core); then there is nothing to unregister from.
  if (!impl.loop_lifetime.expired()) {
    for (auto& port : impl.ports) {
      if (port && port->fd() >= 0) impl.loop->Remove(port->fd());
    }
    impl.loop->Remove(impl.timer_fd.get());
    impl.loop->SetAfterBatch(nullptr);
  }
  impl.timer_fd.Reset();
  impl.loop = nullptr;
}

TimeNs BridgeCore::VirtualNowNs() const {
  if (impl_->stopped_at_ns >= 0) return impl_->stopped_at_ns;
  if (!impl_->loop) return impl_->lockstep_until_ns;
  return impl_->VirtualOf(MonotonicNowNs());
}

void BridgeCore::StepLockstep(TimeNs until_ns) {
  SITLNET_DEMAND(impl_->loop == nullptr);
  const TimeNs from_ns = impl_->lockstep_until_ns;
  SITLNET_DEMAND(until_ns > from_ns);
  struct Pending {
    TimeNs at_ns;
    int robot;
    int order;
    std::vector<uint8_t> frame;
  };
  std::vector<Pending> pending;
  // Robot index order, then the order read from that robot's TAP; each frame
  // gets a seeded instant in [from, until), sorted per robot so a robot's own
  // frames keep their order (docs/tapbridge.md, lockstep).
  for (size_t robot = 0; robot < impl_->ports.size(); ++robot) {
    Port* port = impl_->ports[robot].get();
    if (!port) continue;
    std::vector<std::vector<uint8_t>> frames;
    while (frames.size() < kMaxFramesPerRobotPerTurn) {
      const ssize_t n = port->Read(impl_->buffer);
      if (n == 0) break;
      if (n < 0) {
        impl_->DetachRobot(static_cast<int>(robot),
                           SystemErrorMessage("read from wlan0 TAP", static_cast<int>(-n)));
        break;
      }
      frames.emplace_back(impl_->buffer.begin(), impl_->buffer.begin() + n);
    }
    std::uniform_int_distribution<TimeNs> offset(0, until_ns - from_ns - 1);
    std::vector<TimeNs> instants;
    for (size_t k = 0; k < frames.size(); ++k) {
      instants.push_back(from_ns + offset(impl_->robot_rngs[robot]));
    }
    std::sort(instants.begin(), instants.end());
    for (size_t k = 0; k < frames.size(); ++k) {
      pending.push_back(
          Pending{instants[k], static_cast<int>(robot), static_cast<int>(k), std::move(frames[k])});
    }
  }
  std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
    if (a.at_ns != b.at_ns) return a.at_ns < b.at_ns;
    if (a.robot != b.robot) return a.robot < b.robot;
    return a.order < b.order;
  });
  for (const Pending& p : pending) impl_->EnterFrame(p.robot, p.frame, p.at_ns);
  impl_->AdvanceMediumTo(until_ns);
  impl_->lockstep_until_ns = until_ns;
}

void BridgeCore::SetPosition(int robot, double x_m, double y_m, double z_m) {
  SITLNET_DEMAND(robot >= 0 && robot < robot_count());
  // Effective now: run the medium to the present first so the move is not
  // applied retroactively to frames already on the air.
  if (impl_->loop) impl_->AdvanceMediumTo(VirtualNowNs());
  impl_->medium->SetPosition(robot, x_m, y_m, z_m);
  if (impl_->loop) impl_->ArmTimer();
}

void BridgeCore::Detach(int robot, const std::string& reason) { impl_->DetachRobot(robot, reason); }

int BridgeCore::robot_count() const { return static_cast<int>(impl_->ports.size()); }
const Scenario& BridgeCore::scenario() const { return impl_->scenario; }
const PortCounters& BridgeCore::port_counters(int robot) const { return impl_->counters[robot]; }
MediumCounters BridgeCore::medium_counters(int robot) const {
  return impl_->medium->Counters(robot);
}

LatenessStats BridgeCore::TakeLateness() {
  const LatenessStats stats = impl_->interval_lateness.Stats();
  impl_->interval_lateness.Clear();
  return stats;
}

LatenessStats BridgeCore::TotalLateness() const { return impl_->total_lateness.Stats(); }

void BridgeCore::RefreshKernelCounters() {
  for (size_t i = 0; i < impl_->ports.size(); ++i) {
    if (!impl_->ports[i]) continue;
    if (auto dropped = impl_->ports[i]->KernelTxDropped()) {
      impl_->counters[i].kernel_tx_dropped = *dropped;
    }
  }
}

}  // namespace sitlnet::tapbridge
