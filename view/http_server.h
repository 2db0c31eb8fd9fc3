// The HTTP side of `sitlnet view` and `sitlnet run --view`: the page's files (built into the
// web folder at build time) and JSON documents, served by cpp-httplib (docs/view-reference.md
// says why). What the documents are is the caller's (replay.cc, live.cc).
#ifndef SITLNET_VIEW_HTTP_SERVER_H_
#define SITLNET_VIEW_HTTP_SERVER_H_

#include <functional>
#include <map>
#include <memory>
#include <string>

#include "common/common.h"
#include "view/listen_address.h"

namespace sitlnet::view {

class HttpServer {
 public:
  // Serves the files of `web_dir`. Throws Error when the page is not built there (index.html,
  // app.js).
  explicit HttpServer(const std::string& web_dir);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  using Params = std::map<std::string, std::string>;
  // GET `path` answers `document(query parameters)` as JSON, on the server's threads; an Error
  // it throws is HTTP 400 with its line. Add every document before Bind.
  void Json(const std::string& path, std::function<std::string(const Params&)> document);

  // Binds `address` (port 0: a free one). Returns it with the port bound. Throws ListenError
  // "listen ADDR:PORT: <reason>" (in use, not an address of this host, ...).
  ListenAddress Bind(const ListenAddress& address);
  // Answers requests until Stop (from another thread).
  void Run();
  // Returns once Run has returned; Run must be running or about to run.
  void Stop();
  // CPU time so far of the server's threads: the one in Run and every one that has answered a
  // request (what serving costs, apart from the caller's threads). Call before Stop.
  TimeNs CpuNs() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_HTTP_SERVER_H_
