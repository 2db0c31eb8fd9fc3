// What serving the page costs the host: documents and the page's script go out uncompressed
// whatever the browser accepts (cpp-httplib's brotli took 0.25 s of CPU a live document), and
// the server counts the CPU of its own threads.
#include "view/http_server.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <time.h>

#include <filesystem>
#include <string>
#include <thread>

#include "view/test/run_folder_fixture.h"

namespace sitlnet::view {
namespace {

constexpr char kChromiumAcceptEncoding[] = "gzip, deflate, br, zstd";  // Chromium 156's.

TimeNs ThreadCpuNs() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return now.tv_sec * kNsPerS + now.tv_nsec;
}

class HttpServerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    web_dir_ = ::testing::TempDir() + "/http_server_test_web";
    std::filesystem::create_directories(web_dir_);
    testing::WriteFile(web_dir_ + "/index.html", "<!doctype html><title>t</title>");
    // Text that compresses well, as the bundled page does.
    std::string script;
    for (int i = 0; i < 2000; ++i) script += "const a" + std::to_string(i) + " = 1;\n";
    testing::WriteFile(web_dir_ + "/app.js", script);
  }
  std::string web_dir_;
};

TEST_F(HttpServerTest, DocumentsAndTheScriptGoOutUncompressedToABrowserThatAcceptsBrotli) {
  HttpServer server(web_dir_);
  std::string document = "[";
  for (int i = 0; i < 5000; ++i) document += std::to_string(i % 7) + ",";
  document += "0]";
  server.Json("/api/doc", [&](const HttpServer::Params&) { return document; });
  const ListenAddress bound = server.Bind({"127.0.0.1", 0});
  std::thread serving([&] { server.Run(); });

  httplib::Client client(bound.host, bound.port);
  const httplib::Headers headers = {{"Accept-Encoding", kChromiumAcceptEncoding}};
  const auto json = client.Get("/api/doc", headers);
  const auto script = client.Get("/app.js", headers);
  server.Stop();
  serving.join();

  ASSERT_TRUE(json && script);
  EXPECT_EQ(json->status, 200);
  EXPECT_FALSE(json->has_header("Content-Encoding"));
  EXPECT_EQ(json->get_header_value("Content-Type"), "application/json; charset=utf-8");
  EXPECT_EQ(json->body, document);
  EXPECT_EQ(script->status, 200);
  EXPECT_FALSE(script->has_header("Content-Encoding"));
  EXPECT_EQ(script->get_header_value("Content-Type"), "application/javascript; charset=utf-8");
}

TEST_F(HttpServerTest, CountsTheCpuOfTheThreadsThatAnswered) {
  HttpServer server(web_dir_);
  constexpr TimeNs kBurnNs = 50 * kNsPerMs;
  server.Json("/api/burn", [](const HttpServer::Params&) {
    const TimeNs start_ns = ThreadCpuNs();
    while (ThreadCpuNs() - start_ns < kBurnNs) {
    }
    return std::string("{}");
  });
  const ListenAddress bound = server.Bind({"127.0.0.1", 0});
  std::thread serving([&] { server.Run(); });
  httplib::Client client(bound.host, bound.port);
  for (int i = 0; i < 2; ++i) ASSERT_TRUE(client.Get("/api/burn"));
  const TimeNs spent_ns = server.CpuNs();
  server.Stop();
  serving.join();
  // At least what the kernel counted on the threads that burnt; at most that plus what serving
  // two requests and waiting can take.
  EXPECT_GE(spent_ns, 2 * kBurnNs);
  EXPECT_LT(spent_ns, 2 * kBurnNs + 100 * kNsPerMs);
}

}  // namespace
}  // namespace sitlnet::view
