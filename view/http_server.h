// The HTTP side of `sitlnet view`: the page's files (built into the web folder at build time)
// and the JSON endpoints of one run folder, served by cpp-httplib (docs/view.md says why).
#ifndef SITLNET_VIEW_HTTP_SERVER_H_
#define SITLNET_VIEW_HTTP_SERVER_H_

#include <memory>
#include <string>

#include "view/listen_address.h"
#include "view/run_record.h"

namespace sitlnet::view {

class HttpServer {
 public:
  // Serves `record` (kept by reference) and the files of `web_dir`. Throws Error when the page
  // is not built there (index.html, app.js).
  HttpServer(const RunRecord& record, const std::string& web_dir);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  // Binds `address` (port 0: a free one). Returns it with the port bound. Throws ListenError
  // "listen ADDR:PORT: <reason>" (in use, not an address of this host, ...).
  ListenAddress Bind(const ListenAddress& address);
  // Answers requests until Stop (from another thread).
  void Run();
  void Stop();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sitlnet::view

#endif  // SITLNET_VIEW_HTTP_SERVER_H_
