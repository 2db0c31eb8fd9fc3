// `sitlnet view` on a real run folder: a short lockstep flight of three flockers past an
// obstacle, replayed in Debian's Chromium driven by playwright-core
// (view/web/test/check_page.cjs). Oracles: the run's own trajectories.csv and losses.csv.gz.
// Screenshots go to <build>/tests/artifacts/view_browser/. Label `browser` (docs/view.md).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <sstream>

#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

constexpr char kChromium[] = "/usr/bin/chromium";
constexpr double kPixelTolerance = 1.5;
// Slider times the page is checked at (on trajectories.csv's 100 ms grid).
const std::vector<std::string> kTimes = {"2.0", "3.5"};

constexpr char kFlight[] =
    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"flocker\" "
    "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
    "robot { name: \"b\" position_m { x: 0 y: 6 z: 0.2 } image: \"flocker\" "
    "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
    "robot { name: \"c\" position_m { x: 0 y: -6 z: 0.2 } image: \"flocker\" "
    "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n";
constexpr char kExtra[] =
    "obstacle { name: \"wall\" center_m { x: 10 y: -3 z: 5 } size_m { x: 1 y: 4 z: 10 } "
    "yaw_deg: 30 }\n"
    "timing { duration_ms: 4000 pacing: PACING_LOCKSTEP }\n";

std::string PlaywrightDir() { return integration_test::SourceDir() + "/view/web"; }

// Why the page cannot be driven here (and how to make it so), or "".
std::string BrowserMissing() {
  if (access(kChromium, X_OK) != 0) {
    return std::string("no ") + kChromium +
           " (Debian's Chromium: sudo apt-get install --no-install-recommends chromium, or "
           "sudo scripts/setup)";
  }
  if (!std::filesystem::exists(PlaywrightDir() + "/node_modules/playwright-core")) {
    return "no view/web/node_modules/playwright-core (sudo scripts/setup runs npm ci there)";
  }
  if (RunCommand({"node", "--version"}).exit_code != 0) return "no node (sudo scripts/setup)";
  return "";
}

// The run folder of the flight, made once for the tests of this file; "" with *why if it failed.
const std::string& FlightFolder(std::string* why) {
  static std::string folder, failure;
  static bool done = false;
  if (!done) {
    done = true;
    const RunScenario scenario = WriteScenario(7, kFlight, kExtra);
    DownGuard guard(scenario.name);
    const std::string out = TempDir() + "/" + scenario.name + "-view";
    const CommandResult run = SitlnetRun(scenario, out, {});
    if (run.exit_code == 0) folder = out;
    else failure = "sitlnet run exited " + std::to_string(run.exit_code) + ": " + run.err;
  }
  *why = failure;
  return folder;
}

// losses.csv.gz's lines, header dropped.
std::vector<std::string> LossLines(const std::string& path) {
  std::vector<std::string> lines;
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) return lines;
  std::string text;
  char buffer[65536];
  for (int n; (n = gzread(file, buffer, sizeof buffer)) > 0;) text.append(buffer, n);
  gzclose(file);
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  if (!lines.empty()) lines.erase(lines.begin());
  return lines;
}

// `sitlnet view DIR ARGS...` in the background, and the URL it prints.
struct ViewServer {
  explicit ViewServer(const std::string& dir)
      : child({integration_test::SitlnetBinary(), "view", dir, "--listen", "127.0.0.1:0"}) {
    if (child.WaitForOutput(false, "/\n", 30 * kNsPerS)) {
      const size_t at = child.out().find("http://");
      if (at != std::string::npos) url = child.out().substr(at, child.out().find('\n') - at);
    }
  }
  integration_test::Child child;
  std::string url;
};

TEST(ViewBrowserTest, ReplayDrawsTheTrajectoriesAndListsALinksFramesAsTheLossFile) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE(BrowserMissing());
  std::string why;
  const std::string& dir = FlightFolder(&why);
  ASSERT_FALSE(dir.empty()) << why;
  ViewServer server(dir);
  ASSERT_FALSE(server.url.empty()) << server.child.out() << server.child.err();

  const char* build = std::getenv("SITLNET_BINARY_DIR");
  const std::string artifacts =
      std::string(build ? build : TempDir().c_str()) + "/tests/artifacts/view_browser";
  std::vector<std::string> argv = {"node", PlaywrightDir() + "/test/check_page.cjs", server.url,
                                   artifacts};
  argv.insert(argv.end(), kTimes.begin(), kTimes.end());
  const CommandResult page = RunCommand(argv, 120 * kNsPerS);
  ASSERT_EQ(page.exit_code, 0) << page.out << page.err;

  double px_per_m = 0, min_x_m = 0, max_y_m = 0;
  std::map<std::string, std::map<int, std::pair<double, double>>> drawn;  // time -> robot -> px
  std::vector<std::string> frame_rows;
  long long from = -2, station = -2, start_ns = 0, end_ns = 0, total = -1;
  int screenshots = 0;
  std::istringstream lines(page.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string kind;
    fields >> kind;
    EXPECT_NE(kind, "console_error") << line;
    if (kind == "load_ms") std::printf("page loaded and drawn in %s\n", line.c_str() + 8);
    if (kind == "scale") fields >> px_per_m >> min_x_m >> max_y_m;
    if (kind == "robot") {
      std::string time;
      int robot = -1;
      double x = 0, y = 0;
      fields >> time >> robot >> x >> y;
      drawn[time][robot] = {x, y};
    }
    if (kind == "frames") fields >> from >> station >> start_ns >> end_ns >> total;
    if (kind == "frame") frame_rows.push_back(line.substr(6));
    if (kind == "screenshot") {
      std::string path;
      fields >> path;
      EXPECT_TRUE(std::filesystem::file_size(path) > 1000) << path;
      ++screenshots;
    }
  }
  EXPECT_EQ(screenshots, static_cast<int>(kTimes.size()) + 1);
  ASSERT_GT(px_per_m, 0) << page.out;

  // Each robot where trajectories.csv puts it at the slider's time, within kPixelTolerance at
  // the page's scale; and the slider moved them.
  const std::string trajectories = integration_test::ReadAll(dir + "/trajectories.csv");
  for (int robot = 0; robot < 3; ++robot) {
    const std::vector<TrajectoryRow> rows = TrajectoryRows(trajectories, robot);
    std::vector<std::pair<double, double>> at_times;
    for (const std::string& time : kTimes) {
      const auto row = std::find_if(rows.begin(), rows.end(), [&](const TrajectoryRow& r) {
        return std::abs(r.t_s - std::stod(time)) < 1e-6;
      });
      ASSERT_NE(row, rows.end()) << time;
      ASSERT_EQ(drawn[time].count(robot), 1u) << "robot " << robot << " at " << time;
      const auto [x_px, y_px] = drawn[time][robot];
      EXPECT_NEAR(x_px, (row->x_m - min_x_m) * px_per_m, kPixelTolerance)
          << "robot " << robot << " at " << time << " s";
      EXPECT_NEAR(y_px, (max_y_m - row->y_m) * px_per_m, kPixelTolerance)
          << "robot " << robot << " at " << time << " s";
      at_times.push_back({row->x_m, row->y_m});
    }
    EXPECT_GT(std::hypot(at_times[1].first - at_times[0].first,
                         at_times[1].second - at_times[0].second) * px_per_m, 5)
        << "robot " << robot << " did not move on the page";
  }

  // The clicked link's list: losses.csv.gz's rows of that link (transmitter `from`, station
  // `station`) in the last whole second before the slider's time, in time order.
  const long long second = static_cast<long long>(std::floor(std::stod(kTimes.back()))) - 1;
  EXPECT_EQ(start_ns, second * kNsPerS);
  EXPECT_EQ(end_ns, (second + 1) * kNsPerS);
  std::vector<std::pair<long long, std::string>> expected;
  for (const std::string& line : LossLines(dir + "/losses.csv.gz")) {
    // time_ns,from,to,kind,seq,retry,station,...
    std::vector<std::string> cells;
    std::istringstream split(line);
    for (std::string cell; std::getline(split, cell, ',');) cells.push_back(cell);
    ASSERT_GE(cells.size(), 7u) << line;
    const long long time_ns = std::stoll(cells[0]);
    const int row_from = std::stoi(cells[1]);
    const int row_station = std::stoi(cells[6]);
    if (row_from == from && row_station == station && time_ns >= start_ns && time_ns < end_ns) {
      expected.push_back({time_ns, line});
    }
  }
  std::stable_sort(expected.begin(), expected.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  ASSERT_FALSE(expected.empty()) << "no losses.csv.gz row for link " << from << " -> "
                                 << station;
  EXPECT_EQ(total, static_cast<long long>(expected.size()));
  ASSERT_EQ(frame_rows.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(frame_rows[i], expected[i].second);

  kill(server.child.pid(), SIGTERM);
  EXPECT_EQ(server.child.Wait(10 * kNsPerS), 0) << server.child.err();
}

// The refusals are one line each, before anything is served.
TEST(ViewBrowserTest, APortInUseANonLocalAddressAndAnIncompleteFolderAreOneLine) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  std::string why;
  const std::string& dir = FlightFolder(&why);
  ASSERT_FALSE(dir.empty()) << why;
  const std::string sitlnet = integration_test::SitlnetBinary();

  const int taken = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(taken, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  ASSERT_EQ(bind(taken, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(listen(taken, 1), 0);
  ASSERT_EQ(getsockname(taken, reinterpret_cast<sockaddr*>(&address), &length), 0);
  const std::string in_use = "127.0.0.1:" + std::to_string(ntohs(address.sin_port));
  const CommandResult busy = RunCommand({sitlnet, "view", dir, "--listen", in_use});
  close(taken);
  EXPECT_EQ(busy.exit_code, 1);
  EXPECT_EQ(busy.err, "sitlnet view: listen " + in_use + ": Address already in use\n");

  const CommandResult remote = RunCommand({sitlnet, "view", dir, "--listen", "0.0.0.0:7300"});
  EXPECT_EQ(remote.exit_code, 2);
  EXPECT_EQ(remote.err,
            "sitlnet view: listen address \"0.0.0.0:7300\": not a loopback address; anyone who "
            "reaches it sees the run (add --allow-remote to serve it there)\n");

  const std::string partial = TempDir() + "/view-partial";
  std::filesystem::create_directories(partial);
  std::filesystem::copy_file(dir + "/summary.json", partial + "/summary.json",
                             std::filesystem::copy_options::overwrite_existing);
  const CommandResult incomplete = RunCommand({sitlnet, "view", partial});
  EXPECT_EQ(incomplete.exit_code, 2);
  EXPECT_EQ(incomplete.err, "sitlnet view: run folder \"" + partial +
                                "\" is incomplete: no scenario.textproto (the run did not "
                                "finish)\n");
  EXPECT_EQ(busy.out + remote.out + incomplete.out, "");
}

}  // namespace
}  // namespace sitlnet::nns::testing
