#include "view/http_server.h"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <cstdlib>

#include "common/common.h"
#include "view/replay_json.h"

namespace sitlnet::view {
namespace {

constexpr char kJson[] = "application/json";

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
  const int fd = socket(storage.ss_family, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return SystemErrorMessage("socket", errno);
  const int yes = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);  // As cpp-httplib does.
  std::string why = "refused";
  if (bind(fd, reinterpret_cast<sockaddr*>(&storage), length) != 0) {
    why = std::strerror(errno);
  } else if (listen(fd, 1) != 0) {
    why = std::strerror(errno);
  }
  close(fd);
  return why;
}

bool IsFile(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

// A query parameter as a number, or throws Error naming it.
double NumberParam(const httplib::Request& request, const char* name, const double* fallback) {
  if (!request.has_param(name)) {
    if (fallback != nullptr) return *fallback;
    throw Error(std::string("missing parameter ") + name);
  }
  const std::string text = request.get_param_value(name);
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value)) {
    throw Error(std::string("parameter ") + name + " \"" + text + "\" is not a number");
  }
  return value;
}

}  // namespace

struct HttpServer::Impl {
  httplib::Server server;
};

HttpServer::HttpServer(const RunRecord& record, const std::string& web_dir)
    : impl_(std::make_unique<Impl>()) {
  for (const char* file : {"index.html", "app.js"}) {
    if (!IsFile(web_dir + "/" + file)) {
      throw Error("the page is not built: no " + web_dir + "/" + file +
                  " (scripts/setup installs view/web's npm packages; then build sitlnet_view_page)");
    }
  }
  httplib::Server& server = impl_->server;
  // Everything the page loads comes from this server: no CDN, works offline.
  server.set_default_headers({{"Content-Security-Policy", "default-src 'self'"},
                              {"Cache-Control", "no-store"}});
  server.set_mount_point("/", web_dir);
  // The documents that do not change are built once.
  auto run = std::make_shared<std::string>(RunJson(record));
  auto trajectories = std::make_shared<std::string>(TrajectoriesJson(record));
  auto links = std::make_shared<std::string>(LinksJson(record));
  const auto constant = [](std::shared_ptr<std::string> json) {
    return [json](const httplib::Request&, httplib::Response& response) {
      response.set_content(*json, kJson);
    };
  };
  server.Get("/api/run", constant(run));
  server.Get("/api/trajectories", constant(trajectories));
  server.Get("/api/links", constant(links));
  server.Get("/api/summary", constant(std::make_shared<std::string>(record.summary_json)));
  server.Get("/api/frames", [&record](const httplib::Request& request,
                                      httplib::Response& response) {
    try {
      const double one_second = 1;
      const double from = NumberParam(request, "from", nullptr);
      const double station = NumberParam(request, "to", nullptr);
      const double end_s = NumberParam(request, "t", nullptr);
      const double window_s = NumberParam(request, "window", &one_second);
      response.set_content(FramesJson(record, static_cast<int>(from), static_cast<int>(station),
                                      static_cast<TimeNs>(std::llround(end_s * kNsPerS)),
                                      static_cast<TimeNs>(std::llround(window_s * kNsPerS))),
                           kJson);
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

void HttpServer::Run() { impl_->server.listen_after_bind(); }

void HttpServer::Stop() { impl_->server.stop(); }

}  // namespace sitlnet::view
