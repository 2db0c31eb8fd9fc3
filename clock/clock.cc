#include "clock/clock.h"

#include <poll.h>

#include <cerrno>
#include <cmath>
#include <ctime>
#include <limits>
#include <sstream>

namespace sitlnet::clock {
namespace {

__extension__ using Wide = __int128;

// floor(a / b) and ceil(a / b) for b > 0 (C++ division truncates toward zero).
Wide FloorDiv(Wide a, Wide b) { return a / b - ((a % b != 0) && (a < 0)); }
Wide CeilDiv(Wide a, Wide b) { return a / b + ((a % b != 0) && (a > 0)); }

TimeNs Saturate(Wide value) {
  constexpr Wide kMax = std::numeric_limits<TimeNs>::max();
  constexpr Wide kMin = std::numeric_limits<TimeNs>::min();
  return static_cast<TimeNs>(value > kMax ? kMax : value < kMin ? kMin : value);
}

}  // namespace

TimeNs SystemWallClock::NowNs() { return MonotonicNowNs(); }

void SystemWallClock::SleepUntilNs(TimeNs wall_ns) {
  timespec until{static_cast<time_t>(wall_ns / kNsPerS), static_cast<long>(wall_ns % kNsPerS)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &until, nullptr) == EINTR) {
  }
}

bool SystemWallClock::SleepUntilOrInterruptedNs(TimeNs wall_ns, int interrupt_fd) {
  if (interrupt_fd < 0) {
    SleepUntilNs(wall_ns);
    return true;
  }
  for (;;) {
    const TimeNs left_ns = wall_ns - NowNs();
    if (left_ns <= 0) return true;
    pollfd p{interrupt_fd, POLLIN, 0};
    const timespec timeout{static_cast<time_t>(left_ns / kNsPerS),
                           static_cast<long>(left_ns % kNsPerS)};
    if (ppoll(&p, 1, &timeout, nullptr) > 0 && (p.revents & POLLIN)) return false;
  }
}

WallClock& DefaultWallClock() {
  static SystemWallClock clock;
  return clock;
}

TimeNs CalendarNsOfWall(TimeNs wall_ns) {
  timespec realtime{};
  clock_gettime(CLOCK_REALTIME, &realtime);
  const TimeNs wall_now_ns = MonotonicNowNs();
  return Saturate(Wide{realtime.tv_sec} * kNsPerS + realtime.tv_nsec -
                  (wall_now_ns - Wide{wall_ns}));
}

std::string CheckRealtimeFactor(double factor) {
  if (std::isfinite(factor) && factor >= kMinRealtimeFactor && factor <= kMaxRealtimeFactor) {
    return "";
  }
  std::ostringstream why;
  why << "realtime_factor " << factor << " must be in [" << kMinRealtimeFactor << ", "
      << kMaxRealtimeFactor << "] (virtual seconds per wall second)";
  return why.str();
}

Timebase::Timebase(double realtime_factor) : realtime_factor_(realtime_factor) {
  if (const std::string why = CheckRealtimeFactor(realtime_factor); !why.empty()) {
    throw Error(why);
  }
  // A double is mantissa * 2^exponent exactly; with a 53-bit integer mantissa the conversions
  // below are exact integer arithmetic.
  int exponent = 0;
  const double fraction = std::frexp(realtime_factor, &exponent);  // in [0.5, 1)
  mantissa_ = static_cast<int64_t>(std::ldexp(fraction, 53));
  exponent_ = exponent - 53;
  while (mantissa_ % 2 == 0) {
    mantissa_ /= 2;
    ++exponent_;
  }
}

// ceil(v / (m * 2^e)) and floor(w * m * 2^e), exact and unsaturated: |v|, |w| < 2^64 and a
// factor in range keep them below 2^127.
Wide Timebase::WideWallSpan(TimeNs virtual_span_ns) const {
  const Wide v = virtual_span_ns;
  if (exponent_ >= 0) return CeilDiv(v, Wide{mantissa_} << exponent_);
  return CeilDiv(v << -exponent_, Wide{mantissa_});
}

Wide Timebase::WideVirtualSpan(Wide wall_span_ns) const {
  const Wide product = wall_span_ns * mantissa_;
  if (exponent_ >= 0) return product << exponent_;
  return FloorDiv(product, Wide{1} << -exponent_);
}

void Timebase::BeginAt(TimeNs virtual_ns, TimeNs wall_now_ns) {
  // The latest origin with VirtualOf(wall_now_ns) >= virtual_ns is wall_now - WallSpanOf(v);
  // VirtualSpanOf(WallSpanOf(v)) >= v, and for the whole nanoseconds that follow it grows, so
  // the run's clock never reads behind what the driver was told is now.
  wall_origin_ns_ = Saturate(Wide{wall_now_ns} - WideWallSpan(virtual_ns));
}

// Instants are computed in 128 bits before saturating, like spans: an origin plus a span past
// int64 is "never" (INT64_MAX), not a wrapped-around instant in the past.
TimeNs Timebase::WallOf(TimeNs virtual_ns) const {
  return Saturate(Wide{wall_origin_ns_} + WideWallSpan(virtual_ns));
}

TimeNs Timebase::VirtualOf(TimeNs wall_ns) const {
  return Saturate(WideVirtualSpan(Wide{wall_ns} - wall_origin_ns_));
}

TimeNs Timebase::LagNs(TimeNs virtual_ns, TimeNs wall_now_ns) const {
  const TimeNs due_ns = WallOf(virtual_ns);
  return wall_now_ns > due_ns ? Saturate(Wide{wall_now_ns} - due_ns) : 0;
}

TimeNs Timebase::WallSpanOf(TimeNs virtual_span_ns) const {
  return Saturate(WideWallSpan(virtual_span_ns));
}

TimeNs Timebase::VirtualSpanOf(TimeNs wall_span_ns) const {
  return Saturate(WideVirtualSpan(wall_span_ns));
}

TimeNs TickTimeNs(int64_t tick, int64_t rate_hz) {
  SITLNET_DEMAND(rate_hz > 0 && tick >= 0);
  return Saturate(Wide{tick} * kNsPerS / rate_hz);
}

bool SleepUntilVirtual(const Timebase& timebase, TimeNs virtual_ns, WallClock& wall_clock,
                       int interrupt_fd) {
  return wall_clock.SleepUntilOrInterruptedNs(timebase.WallOf(virtual_ns), interrupt_fd);
}

}  // namespace sitlnet::clock
