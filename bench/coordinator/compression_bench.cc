// Where zlib pays: encode+decode cost of an End message with N robot poses,
// raw and zlib level 1, and one-way transfer time over Unix and TCP loopback
// sockets (ping-pong between two threads). From these, the link rate below
// which compressing saves time: bytes saved · 8 / extra CPU time.
#include <unistd.h>

#include <cstdio>
#include <ctime>
#include <string>
#include <thread>

#include "coordinator/coordinator.h"
#include "coordinator/synthetic.h"

namespace sitlnet::coordinator {
namespace {

proto::coord::CoordinatorMessage EndMessage(int robots) {
  proto::coord::CoordinatorMessage message;
  message.mutable_end()->set_iteration(1234);
  message.mutable_end()->set_busy_ns(987654);
  // Poses of robots in flight at an arbitrary instant: full-precision
  // doubles, as physics reports them.
  SyntheticPhysics::PosesAt(robots, 12'345'678'901, message.mutable_end()->mutable_poses());
  return message;
}

// CPU time of the calling thread: unlike wall time, not inflated when other
// processes share the 2 cores.
TimeNs ThreadCpuNs() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return TimeNs{ts.tv_sec} * kNsPerS + ts.tv_nsec;
}

// Mean CPU ns per encode+decode round of `message` with `options`.
double CodecNs(const proto::coord::CoordinatorMessage& message, const FrameCodecOptions& options,
               size_t* frame_bytes) {
  FrameEncoder encoder(options);
  FrameScratch scratch;
  proto::coord::CoordinatorMessage decoded;
  auto once = [&] {
    const std::string_view frame = encoder.Encode(message);
    FrameEncoding encoding{};
    ParseFrameHeader(reinterpret_cast<const uint8_t*>(frame.data()), options.max_frame_bytes,
                     &encoding);
    DecodeFrameBody(encoding, frame.substr(kFrameHeaderBytes), options.max_frame_bytes, &scratch,
                    &decoded);
    *frame_bytes = frame.size();
  };
  once();
  int reps = 1;
  for (;;) {
    const TimeNs t0 = ThreadCpuNs();
    for (int i = 0; i < reps; ++i) once();
    const TimeNs elapsed = ThreadCpuNs() - t0;
    if (elapsed > 50 * kNsPerMs) return static_cast<double>(elapsed) / reps;
    reps *= 2;
  }
}

// Mean one-way ns (round trip / 2) of `message` between two threads.
double OneWayNs(const Endpoint& where, const proto::coord::CoordinatorMessage& message,
                const FrameCodecOptions& options, int rounds) {
  Listener listener(where);
  std::thread echo([&] {
    Channel channel(Connect(listener.endpoint(), MonotonicNowNs() + 5 * kNsPerS), options);
    proto::coord::CoordinatorMessage in;
    for (int i = 0; i < rounds + 10; ++i) {
      channel.Receive(&in);
      channel.Send(in);
    }
  });
  Channel channel(listener.Accept(MonotonicNowNs() + 5 * kNsPerS), options);
  proto::coord::CoordinatorMessage in;
  for (int i = 0; i < 10; ++i) {  // Warm-up.
    channel.Send(message);
    channel.Receive(&in);
  }
  const TimeNs t0 = MonotonicNowNs();
  for (int i = 0; i < rounds; ++i) {
    channel.Send(message);
    channel.Receive(&in);
  }
  const TimeNs elapsed = MonotonicNowNs() - t0;
  echo.join();
  return static_cast<double>(elapsed) / rounds / 2;
}

}  // namespace

int RunCompressionBench() {
  std::printf(
      "| robots | frame B raw | frame B zlib | ratio | codec CPU µs raw | codec CPU µs zlib "
      "| UDS one-way µs raw | zlib | TCP lo one-way µs raw | zlib | zlib pays below |\n");
  std::printf("| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n");
  FrameCodecOptions raw;
  FrameCodecOptions zlib;
  zlib.compress_above_bytes = 0;
  const std::string uds = "unix:/tmp/sitlnet-bench-zlib-" + std::to_string(getpid()) + ".sock";
  for (int robots : {1, 8, 32, 64, 256, 1024, 4096}) {
    const proto::coord::CoordinatorMessage message = EndMessage(robots);
    size_t raw_bytes = 0, zlib_bytes = 0;
    const double raw_ns = CodecNs(message, raw, &raw_bytes);
    const double zlib_ns = CodecNs(message, zlib, &zlib_bytes);
    const int rounds = robots >= 1024 ? 300 : 2000;
    const double uds_raw = OneWayNs(ParseEndpoint(uds), message, raw, rounds);
    const double uds_zlib = OneWayNs(ParseEndpoint(uds), message, zlib, rounds);
    const double tcp_raw = OneWayNs(ParseEndpoint("127.0.0.1:0"), message, raw, rounds);
    const double tcp_zlib = OneWayNs(ParseEndpoint("127.0.0.1:0"), message, zlib, rounds);
    // Compressing saves (raw - zlib) bytes on the wire for (zlib_ns - raw_ns)
    // of CPU: it pays on links slower than saved_bits / extra_seconds.
    const double saved_bits = 8.0 * (static_cast<double>(raw_bytes) - zlib_bytes);
    const double extra_s = (zlib_ns - raw_ns) * 1e-9;
    char pays[64];
    if (saved_bits <= 0) {
      std::snprintf(pays, sizeof pays, "never (no gain)");
    } else {
      std::snprintf(pays, sizeof pays, "%.0f Mb/s", saved_bits / extra_s / 1e6);
    }
    std::printf("| %d | %zu | %zu | %.2f | %.2f | %.2f | %.1f | %.1f | %.1f | %.1f | %s |\n",
                robots, raw_bytes, zlib_bytes,
                static_cast<double>(zlib_bytes) / static_cast<double>(raw_bytes), raw_ns / 1e3,
                zlib_ns / 1e3, uds_raw / 1e3, uds_zlib / 1e3, tcp_raw / 1e3, tcp_zlib / 1e3, pays);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace sitlnet::coordinator
