// Preloaded beside libfaketime in dilated time (docs/time.md): scales the socket timeouts a
// program sets (SO_RCVTIMEO, SO_SNDTIMEO), which the kernel counts in host time and libfaketime
// does not intercept. A program asking for a wait of t seconds of its (dilated) time gets a
// kernel timeout of t / f host seconds, f = SITLNET_TIME_FACTOR (virtual seconds per host
// second); getsockopt reads back the program's own value. iputils ping waits between requests
// this way: without this library, at f = 2 it sent one request per interval of host time.
//
// Plain C interfaces only: it is loaded into arbitrary programs, so it throws nothing, allocates
// nothing and needs no C++ runtime.
#include <dlfcn.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>

namespace {

using SetsockoptFn = int (*)(int, int, int, const void*, socklen_t);
using GetsockoptFn = int (*)(int, int, int, void*, socklen_t*);

// Virtual seconds per host second; 0: not set or not valid, timeouts pass unchanged.
double g_factor = 0;
SetsockoptFn g_setsockopt = nullptr;
GetsockoptFn g_getsockopt = nullptr;

// libc's functions; also from the calls themselves, which another library's constructor may
// make before this one's has run.
void ResolveNext() {
  if (g_setsockopt == nullptr) {
    g_setsockopt = reinterpret_cast<SetsockoptFn>(dlsym(RTLD_NEXT, "setsockopt"));
  }
  if (g_getsockopt == nullptr) {
    g_getsockopt = reinterpret_cast<GetsockoptFn>(dlsym(RTLD_NEXT, "getsockopt"));
  }
}

__attribute__((constructor)) void Load() {
  ResolveNext();
  const char* text = std::getenv("SITLNET_TIME_FACTOR");
  if (text == nullptr) return;
  char* end = nullptr;
  const double factor = std::strtod(text, &end);
  if (end != text && *end == '\0' && std::isfinite(factor) && factor > 0) g_factor = factor;
}

bool IsSocketTimeout(int level, int name) {
  return level == SOL_SOCKET && (name == SO_RCVTIMEO || name == SO_SNDTIMEO);
}

// t seconds of one clock as seconds of a clock running `scale` times as fast, in whole
// microseconds; a non-zero timeout stays non-zero (zero means "no timeout" to the kernel).
timeval Scaled(const timeval& t, double scale) {
  if (t.tv_sec < 0 || t.tv_usec < 0 || t.tv_usec >= 1000000) return t;  // The kernel refuses it.
  const double scaled_us = std::ceil((static_cast<double>(t.tv_sec) * 1e6 + t.tv_usec) * scale);
  if (scaled_us == 0 || !(scaled_us < 9.2e18)) return t;
  const auto us = static_cast<int64_t>(scaled_us);
  timeval out{};
  out.tv_sec = static_cast<time_t>(us / 1000000);
  out.tv_usec = static_cast<suseconds_t>(us % 1000000);
  return out;
}

}  // namespace

extern "C" int setsockopt(int fd, int level, int name, const void* value, socklen_t length) {
  ResolveNext();
  if (g_setsockopt == nullptr) {
    errno = ENOSYS;
    return -1;
  }
  if (g_factor == 0 || !IsSocketTimeout(level, name) || value == nullptr ||
      length < static_cast<socklen_t>(sizeof(timeval))) {
    return g_setsockopt(fd, level, name, value, length);
  }
  const timeval host = Scaled(*static_cast<const timeval*>(value), 1 / g_factor);
  return g_setsockopt(fd, level, name, &host, sizeof host);
}

extern "C" int getsockopt(int fd, int level, int name, void* value, socklen_t* length) {
  ResolveNext();
  if (g_getsockopt == nullptr) {
    errno = ENOSYS;
    return -1;
  }
  const int result = g_getsockopt(fd, level, name, value, length);
  if (result == 0 && g_factor != 0 && IsSocketTimeout(level, name) && value != nullptr &&
      length != nullptr && *length >= static_cast<socklen_t>(sizeof(timeval))) {
    *static_cast<timeval*>(value) = Scaled(*static_cast<timeval*>(value), g_factor);
  }
  return result;
}
