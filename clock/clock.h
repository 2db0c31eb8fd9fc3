// sitlnet's one owner of time: the run's virtual time (integer nanoseconds since the scenario
// starts), its wall origin and realtime factor, the mapping between virtual and wall time, waits
// for "virtual time t has come", and lag.
//
// Every module that converts between virtual and wall time goes through Timebase, so they all
// round the same way (docs/time.md):
//   wall(v)    = origin + ceil(v / factor)      the first wall nanosecond at which v has come
//   virtual(w) = floor((w - origin) * factor)   the virtual time that has fully come at w
// Both are exact (the factor is a double, i.e. an exact binary fraction; the arithmetic is done
// in 128-bit integers), so virtual(wall(v)) >= v and wall(virtual(w)) <= w always hold: nothing
// released at wall(v) goes out before v, and no one reads a virtual time that has not come.
#ifndef SITLNET_CLOCK_CLOCK_H_
#define SITLNET_CLOCK_CLOCK_H_

#include "common/common.h"

namespace sitlnet::clock {

//---------------------------------- Wall clocks ----------------------------------

// A monotonic wall clock (nanoseconds, arbitrary origin). Injected so that code that paces
// itself can be tested without sleeping.
class WallClock {
 public:
  virtual ~WallClock() = default;
  virtual TimeNs NowNs() = 0;
  // Returns once NowNs() >= wall_ns (at once if already past).
  virtual void SleepUntilNs(TimeNs wall_ns) = 0;
  // Same, but returns false early if `interrupt_fd` (>= 0) becomes readable.
  // Default: not interruptible.
  virtual bool SleepUntilOrInterruptedNs(TimeNs wall_ns, int interrupt_fd) {
    SleepUntilNs(wall_ns);
    return true;
  }
};

// CLOCK_MONOTONIC; sleeps with clock_nanosleep(TIMER_ABSTIME) so deadlines do not drift with
// the time spent computing.
class SystemWallClock final : public WallClock {
 public:
  TimeNs NowNs() override;
  void SleepUntilNs(TimeNs wall_ns) override;
  // ppoll() on the fd with the time left, re-armed until the deadline.
  bool SleepUntilOrInterruptedNs(TimeNs wall_ns, int interrupt_fd) override;
};

// Process-wide instance of SystemWallClock.
WallClock& DefaultWallClock();

// The CLOCK_REALTIME instant (ns since the Unix epoch) of the CLOCK_MONOTONIC instant `wall_ns`,
// as the two clocks stand now: calendar dates in outputs (a pcap's date of virtual time 0),
// never pacing (CLOCK_REALTIME jumps when the host's time is set).
TimeNs CalendarNsOfWall(TimeNs wall_ns);

//------------------------------ Virtual <-> wall time ------------------------------

// Realtime factors a run may use (virtual seconds per wall second). Outside this range the
// exact arithmetic could overflow for long runs, and no use is known.
inline constexpr double kMinRealtimeFactor = 1.0 / 1024;
inline constexpr double kMaxRealtimeFactor = 1024;

// Empty if `factor` is a usable realtime factor, else why not (one line, for error messages).
std::string CheckRealtimeFactor(double factor);

// The mapping between one run's virtual time and the wall clock (CLOCK_MONOTONIC ns).
// Cheap to copy; not thread-safe to Begin() while another thread converts.
class Timebase {
 public:
  // Throws Error if `realtime_factor` fails CheckRealtimeFactor.
  explicit Timebase(double realtime_factor = 1.0);

  // Virtual time 0 is at wall instant `wall_origin_ns`.
  void Begin(TimeNs wall_origin_ns) { wall_origin_ns_ = wall_origin_ns; }
  // Virtual time `virtual_ns` is now, at wall instant `wall_now_ns` (a driver that joins a run
  // already under way). Afterwards VirtualOf(wall_now_ns) is virtual_ns when the factor is at
  // most 1, and the first virtual time >= virtual_ns that a wall nanosecond maps to above 1.
  void BeginAt(TimeNs virtual_ns, TimeNs wall_now_ns);

  // Wall instant at which virtual time `virtual_ns` has come (the rounding rule above).
  TimeNs WallOf(TimeNs virtual_ns) const;
  // Virtual time that has come at wall instant `wall_ns`.
  TimeNs VirtualOf(TimeNs wall_ns) const;
  // How far `wall_now_ns` is past the instant of `virtual_ns` (0 if not past).
  TimeNs LagNs(TimeNs virtual_ns, TimeNs wall_now_ns) const;
  // The same conversions for durations: ceil(virtual_span / factor), floor(wall_span * factor).
  TimeNs WallSpanOf(TimeNs virtual_span_ns) const;
  TimeNs VirtualSpanOf(TimeNs wall_span_ns) const;

  double realtime_factor() const { return realtime_factor_; }
  TimeNs wall_origin_ns() const { return wall_origin_ns_; }

 private:
  __extension__ using Wide = __int128;
  Wide WideWallSpan(TimeNs virtual_span_ns) const;
  Wide WideVirtualSpan(Wide wall_span_ns) const;

  double realtime_factor_;
  // realtime_factor_ == mantissa_ * 2^exponent_ exactly, mantissa_ odd (or 1).
  int64_t mantissa_ = 1;
  int exponent_ = 0;
  TimeNs wall_origin_ns_ = 0;
};

// Virtual time of tick `tick` of a clock running at `rate_hz` (e.g. the frames of a lock-step
// autopilot): floor(tick * 1 s / rate_hz), exact, so a rate that does not divide a second
// carries its remainder instead of drifting. Demands rate_hz > 0 and tick >= 0.
TimeNs TickTimeNs(int64_t tick, int64_t rate_hz);

// Sleeps on `wall_clock` until virtual time `virtual_ns` has come by `timebase`. Returns false
// early if `interrupt_fd` (>= 0) becomes readable.
bool SleepUntilVirtual(const Timebase& timebase, TimeNs virtual_ns, WallClock& wall_clock,
                       int interrupt_fd = -1);

}  // namespace sitlnet::clock

#endif  // SITLNET_CLOCK_CLOCK_H_
