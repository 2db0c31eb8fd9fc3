#include "view/http_server.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <fcntl.h>
#include <httplib.h>
#include <netinet/in.h>
#include <pthread.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <mutex>
#include <vector>

#include "common/common.h"

namespace sitlnet::view {
namespace {

// Content types cpp-httplib does not compress. It compresses "application/json", JavaScript
// and text with brotli when the browser accepts it (every browser does), at brotli's default
// quality 11: about 0.25 s of CPU for each 50 kB /api/live, twice a second, on the run's host
// (docs/performance.md, "Live view"). Uncompressed, a document takes 2.5 ms; the page is local
// or behind an SSH tunnel, where 100 kB/s is nothing.
constexpr char kJson[] = "application/json; charset=utf-8";
constexpr char kJavaScript[] = "application/javascript; charset=utf-8";

// Why binding `address` fails, asked of the kernel with a socket of our own (cpp-httplib
// reports only that it failed).
std::string BindFailure(const ListenAddress& address) {
  sockaddr_storage storage{};
  socklen_t length = 0;
  auto* v4 = reinterpret_cast<sockaddr_in*>(&storage);
  auto* v6 = reinterpret_cast<sockaddr_in6*>(&storage);
  if (inet_pton(AF_INET, address.host.c_str(), &v4->sin_addr) == 1) {
    v4->sin_family = AF_INET;
    v4->sin_port = htons(address.port);
    length = sizeof *v4;
  } else if (inet_pton(AF_INET6, address.host.c_str(), &v6->sin6_addr) == 1) {
    v6->sin6_family = AF_INET6;
    v6->sin6_port = htons(address.port);
    length = sizeof *v6;
  } else {
    return "not a numeric address";
  }
  const UniqueFd socket_fd(socket(storage.ss_family, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!socket_fd.valid()) return SystemErrorMessage("socket", errno);
  const int fd = socket_fd.get();
  const int yes = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);  // As cpp-httplib does.
  std::string why = "refused";
  if (bind(fd, reinterpret_cast<sockaddr*>(&storage), length) != 0) {
    why = std::strerror(errno);
  } else if (listen(fd, 1) != 0) {
    why = std::strerror(errno);
  }
  return why;
}

// Every socket of this process but stdin, stdout and stderr made close-on-exec. cpp-httplib
// 0.11 accepts connections with accept(), without SOCK_CLOEXEC, and has no hook there; a robot
// forked by `sitlnet run --view` would inherit a browser's connection. The run opens every
// other descriptor close-on-exec (docs/run.md), so this changes none of its own.
void MarkSocketsCloseOnExec() {
  DIR* fds = opendir("/proc/self/fd");
  if (fds == nullptr) return;
  while (const dirent* entry = readdir(fds)) {
    const int fd = std::atoi(entry->d_name);
    if (fd <= 2 || fd == dirfd(fds)) continue;
    const int flags = fcntl(fd, F_GETFD);
    struct stat info {};
    if (flags >= 0 && !(flags & FD_CLOEXEC) && fstat(fd, &info) == 0 && S_ISSOCK(info.st_mode)) {
      fcntl(fd, F_SETFD, flags | FD_CLOEXEC);
    }
  }
  closedir(fds);
}

bool IsFile(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

}  // namespace

struct HttpServer::Impl {
  httplib::Server server;
  std::mutex mutex;
  std::condition_variable finished_changed;
  bool finished = false;  // Run has returned.
  mutable std::mutex clocks_mutex;
  std::vector<clockid_t> thread_clocks;  // Of the server's threads (CpuNs).

  // Counts the calling thread's CPU time in CpuNs, once per thread, and names it (top -H and
  // /proc/PID/task/TID/comm show "sitlnet-view").
  void CountThisThread() {
    thread_local const Impl* counted_for = nullptr;
    if (counted_for == this) return;
    pthread_setname_np(pthread_self(), "sitlnet-view");
    clockid_t clock;
    if (pthread_getcpuclockid(pthread_self(), &clock) != 0) return;
    std::lock_guard lock(clocks_mutex);
    thread_clocks.push_back(clock);
    counted_for = this;
  }
};

HttpServer::HttpServer(const std::string& web_dir) : impl_(std::make_unique<Impl>()) {
  for (const char* file : {"index.html", "app.js"}) {
    if (!IsFile(web_dir + "/" + file)) {
      throw Error("the page is not built: no " + web_dir + "/" + file +
                  " (scripts/setup installs view/web's npm packages; then build sitlnet_view_page)");
    }
  }
  // Everything the page loads comes from this server: no CDN, works offline.
  impl_->server.set_default_headers({{"Content-Security-Policy", "default-src 'self'"},
                                     {"Cache-Control", "no-store"}});
  impl_->server.set_mount_point("/", web_dir);
  impl_->server.set_file_extension_and_mimetype_mapping("js", kJavaScript);
  // A connection that sends nothing, reads nothing or idles holds a worker thread this long at
  // most, and so delays the server's stop (at the end of a run) at most this long.
  constexpr time_t kConnectionTimeoutS = 1;
  impl_->server.set_read_timeout(kConnectionTimeoutS, 0);
  impl_->server.set_write_timeout(kConnectionTimeoutS, 0);
  impl_->server.set_keep_alive_timeout(kConnectionTimeoutS);
  // The listening socket: cpp-httplib's own options (SO_REUSEADDR), and close-on-exec.
  impl_->server.set_socket_options([](int sock) {
    const int yes = 1;
    setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    fcntl(sock, F_SETFD, fcntl(sock, F_GETFD) | FD_CLOEXEC);
  });
  // Each connection, before it is answered (see MarkSocketsCloseOnExec).
  impl_->server.set_pre_routing_handler([impl = impl_.get()](const httplib::Request&,
                                                             httplib::Response&) {
    impl->CountThisThread();
    MarkSocketsCloseOnExec();
    return httplib::Server::HandlerResponse::Unhandled;
  });
}

void HttpServer::Json(const std::string& path,
                      std::function<std::string(const Params&)> document) {
  impl_->server.Get(path, [document = std::move(document)](const httplib::Request& request,
                                                           httplib::Response& response) {
    Params params;
    for (const auto& [name, value] : request.params) params.emplace(name, value);
    try {
      response.set_content(document(params), kJson);
    } catch (const Error& error) {
      response.status = 400;
      response.set_content(std::string(error.what()) + "\n", "text/plain");
    }
  });
}

HttpServer::~HttpServer() = default;

ListenAddress HttpServer::Bind(const ListenAddress& address) {
  ListenAddress bound = address;
  bool ok;
  if (address.port == 0) {
    bound.port = impl_->server.bind_to_any_port(address.host);
    ok = bound.port > 0;
  } else {
    ok = impl_->server.bind_to_port(address.host, address.port);
  }
  if (!ok) {
    throw ListenError("listen " + HostPort(address) + ": " + BindFailure(address));
  }
  return bound;
}

void HttpServer::Run() {
  impl_->CountThisThread();
  impl_->server.listen_after_bind();
  std::lock_guard lock(impl_->mutex);
  impl_->finished = true;
  impl_->finished_changed.notify_all();
}

void HttpServer::Stop() {
  // cpp-httplib's stop() does nothing before its loop has started: ask again until Run returns.
  constexpr std::chrono::milliseconds kRetry(10);
  std::unique_lock lock(impl_->mutex);
  while (!impl_->finished) {
    impl_->server.stop();
    impl_->finished_changed.wait_for(lock, kRetry);
  }
}

TimeNs HttpServer::CpuNs() const {
  std::lock_guard lock(impl_->clocks_mutex);
  TimeNs total_ns = 0;
  for (const clockid_t clock : impl_->thread_clocks) {
    timespec spent{};
    // A thread that ended (cpp-httplib keeps its workers until Stop) is no longer counted.
    if (clock_gettime(clock, &spent) == 0) total_ns += spent.tv_sec * kNsPerS + spent.tv_nsec;
  }
  return total_ns;
}

}  // namespace sitlnet::view
