// `sitlnet view` on a real run folder: a short lockstep flight of three flockers past an
// obstacle, replayed in Debian's Chromium driven by playwright-core
// (view/web/test/check_page.cjs). Oracles: the run's own trajectories.csv, losses.csv.gz,
// connectivity.csv, metrics.csv and summary.json.
// Screenshots go to <build>/tests/artifacts/view_browser/. Label `browser` (docs/view.md).
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "run_formats/run_formats.h"
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
constexpr char kObstacle[] =
    "obstacle { name: \"wall\" center_m { x: 10 y: -3 z: 5 } size_m { x: 1 y: 4 z: 10 } "
    "yaw_deg: 30 }\n";

std::string PlaywrightDir() { return integration_test::SourceDir() + "/view/web"; }

// Why Chromium cannot be started here, or "": scripts/setup's group "browser" installs it.
std::string ChromiumMissing() {
  return access(kChromium, X_OK) == 0 ? "" : std::string("no ") + kChromium;
}

// Why the page's driver cannot run here (and how to make it so), or "".
std::string PlaywrightMissing() {
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
    const RunScenario scenario = WriteScenario(
        7, kFlight,
        std::string(kObstacle) + "timing { duration_ms: 4000 pacing: PACING_LOCKSTEP }\n");
    DownGuard guard(scenario.name);
    const std::string out = TempDir() + "/" + scenario.name + "-view";
    const CommandResult run = SitlnetRun(scenario, out, {});
    if (run.exit_code == 0)
      folder = out;
    else
      failure = "sitlnet run exited " + std::to_string(run.exit_code) + ": " + run.err;
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

// A robot as the page drew it, with the map's scale then.
struct DrawnRobot {
  std::string time_s;  // The slider's time, or the live sample's.
  int robot = -1;
  double x_px = 0, y_px = 0;
  double px_per_m = 0, min_x_m = 0, max_y_m = 0;
};

// What check_page.cjs printed (its header says each line).
struct PageFacts {
  std::vector<std::string> errors;
  std::vector<DrawnRobot> robots;
  int screenshots = 0;
  // Replay: the clicked link's frame list.
  long long from = -2, station = -2, start_ns = 0, end_ns = 0, total = -1;
  std::vector<std::string> frame_rows;
  // Live: per read, the links.csv second drawn and its links "from,to,frames,delivered".
  std::vector<std::pair<long long, std::set<std::string>>> live_links;
  // Per time (replay) or read (live), the timeline's fields after "timeline TIME_S".
  std::vector<std::vector<std::string>> timelines;
  // Replay: the robot table's mode, "TIME_S ROBOT" -> mode.
  std::map<std::string, std::string> modes;
};

PageFacts ParsePage(const std::string& out) {
  PageFacts facts;
  double px_per_m = 0, min_x_m = 0, max_y_m = 0;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string kind;
    fields >> kind;
    if (kind == "console_error") facts.errors.push_back(line);
    if (kind == "load_ms") std::printf("page loaded and drawn in %s ms\n", line.c_str() + 8);
    if (kind == "scale") fields >> px_per_m >> min_x_m >> max_y_m;
    if (kind == "mode") {
      std::string time_s, robot, mode;
      fields >> time_s >> robot >> mode;
      facts.modes[time_s + " " + robot] = mode;
    }
    if (kind == "robot") {
      DrawnRobot robot;
      robot.px_per_m = px_per_m;
      robot.min_x_m = min_x_m;
      robot.max_y_m = max_y_m;
      fields >> robot.time_s >> robot.robot >> robot.x_px >> robot.y_px;
      facts.robots.push_back(robot);
    }
    if (kind == "frames") {
      fields >> facts.from >> facts.station >> facts.start_ns >> facts.end_ns >> facts.total;
    }
    if (kind == "frame") facts.frame_rows.push_back(line.substr(6));
    if (kind == "live") {
      std::string time;
      long long second = -1;
      fields >> time >> second;
      facts.live_links.push_back({second, {}});
    }
    if (kind == "link" && !facts.live_links.empty()) {
      std::string from, to, frames, delivered;
      fields >> from >> to >> frames >> delivered;
      facts.live_links.back().second.insert(from + "," + to + "," + frames + "," + delivered);
    }
    if (kind == "timeline") {
      facts.timelines.emplace_back();
      for (std::string field; fields >> field;) facts.timelines.back().push_back(field);
    }
    if (kind == "screenshot") {
      std::string path;
      fields >> path;
      EXPECT_GT(std::filesystem::file_size(path), 1000u) << path;
      ++facts.screenshots;
    }
  }
  return facts;
}

// Each drawn robot within kPixelTolerance of its trajectories.csv row at the time drawn, at
// the page's scale then.
void ExpectDrawnWhereTrajectoriesSay(const std::vector<DrawnRobot>& drawn,
                                     const std::string& trajectories) {
  ASSERT_FALSE(drawn.empty());
  for (const DrawnRobot& robot : drawn) {
    ASSERT_GT(robot.px_per_m, 0);
    const std::vector<TrajectoryRow> rows = TrajectoryRows(trajectories, robot.robot);
    const auto row = std::find_if(rows.begin(), rows.end(), [&](const TrajectoryRow& r) {
      return std::abs(r.t_s - std::stod(robot.time_s)) < 1e-6;
    });
    ASSERT_NE(row, rows.end()) << "robot " << robot.robot << " at " << robot.time_s;
    EXPECT_NEAR(robot.x_px, (row->x_m - robot.min_x_m) * robot.px_per_m, kPixelTolerance)
        << "robot " << robot.robot << " at " << robot.time_s << " s";
    EXPECT_NEAR(robot.y_px, (robot.max_y_m - row->y_m) * robot.px_per_m, kPixelTolerance)
        << "robot " << robot.robot << " at " << robot.time_s << " s";
  }
}

// The timeline as check_page.cjs printed it, as numbers ("-": absent, -1).
struct DrawnTimeline {
  double time_s = 0;  // The slider's time, or the live sample's.
  int max_components = 0;
  double cursor_time_s = -1;      // Where its red line is (live: the latest sample).
  double components_time_s = -1;  // The connectivity.csv row shown, where it began.
  int components = -1;
  std::string component_of;  // "c0,c1,..."
  long long timing_second = -1;
  long long iterations = -1;
  double stf_mean = 0, stf_max = 0, lag_max_ms = 0;
};

DrawnTimeline ParseTimeline(const std::vector<std::string>& f) {
  DrawnTimeline t;
  EXPECT_EQ(f.size(), 11u);
  if (f.size() != 11) return t;
  const auto number = [](const std::string& text) { return text == "-" ? -1 : std::stod(text); };
  t.time_s = number(f[0]);
  t.max_components = static_cast<int>(number(f[1]));
  t.cursor_time_s = number(f[2]);
  t.components_time_s = number(f[3]);
  t.components = static_cast<int>(number(f[4]));
  t.component_of = f[5];
  t.timing_second = static_cast<long long>(number(f[6]));
  t.iterations = static_cast<long long>(number(f[7]));
  t.stf_mean = number(f[8]);
  t.stf_max = number(f[9]);
  t.lag_max_ms = number(f[10]);
  return t;
}

// What the page's timeline showed is what the run's files say: the components of the last
// connectivity.csv row at or before its red line (a replay's slider time, the live feed's
// latest sample), the largest count summary.json gives, and the second's iterations in
// metrics.csv.
void ExpectTimelineAsTheRunsFiles(const std::vector<std::vector<std::string>>& printed,
                                  const std::string& dir, bool replay) {
  ASSERT_FALSE(printed.empty());
  struct Row {
    double time_s;
    int components;
    std::string component_of;
  };
  std::vector<Row> rows;
  std::istringstream connectivity(integration_test::ReadAll(dir + "/connectivity.csv"));
  std::string line;
  std::getline(connectivity, line);  // The header.
  while (std::getline(connectivity, line)) {
    const size_t first = line.find(','), second = line.find(',', first + 1);
    rows.push_back({std::stod(line.substr(0, first)),
                    std::stoi(line.substr(first + 1, second - first - 1)),
                    line.substr(second + 1)});
  }
  ASSERT_FALSE(rows.empty());
  const std::string summary = integration_test::ReadAll(dir + "/summary.json");
  const size_t at = summary.find("\"max_components\":");
  ASSERT_NE(at, std::string::npos) << summary;
  const int max_components = std::stoi(summary.substr(at + 17));
  // metrics.csv: iteration,start_ns,t_phy_ns,t_net_ns,t_total_ns,t_overhead_ns,stf,lag_ns
  std::map<long long, std::vector<std::pair<double, long long>>> by_second;
  std::istringstream metrics(integration_test::ReadAll(dir + "/metrics.csv"));
  std::getline(metrics, line);
  while (std::getline(metrics, line)) {
    long long iteration = 0, start_ns = 0, phy = 0, net = 0, total = 0, overhead = 0, lag = 0;
    double stf = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lld,%lld,%lld,%lld,%lld,%lld,%lf,%lld", &iteration,
                          &start_ns, &phy, &net, &total, &overhead, &stf, &lag),
              8)
        << line;
    by_second[start_ns / kNsPerS].push_back({stf, lag});
  }

  for (const std::vector<std::string>& fields : printed) {
    const DrawnTimeline drawn = ParseTimeline(fields);
    SCOPED_TRACE("timeline at " + std::to_string(drawn.time_s) + " s");
    if (replay) {
      EXPECT_EQ(drawn.max_components, max_components);
      EXPECT_NEAR(drawn.cursor_time_s, drawn.time_s, 1e-9);
    } else {  // The latest sample is a row of the file.
      EXPECT_TRUE(std::any_of(rows.begin(), rows.end(), [&](const Row& r) {
        return std::abs(r.time_s - drawn.cursor_time_s) < 1e-6;
      })) << drawn.cursor_time_s;
    }
    const auto row = std::find_if(rows.rbegin(), rows.rend(), [&](const Row& r) {
      return r.time_s <= drawn.cursor_time_s + 1e-6;
    });
    ASSERT_NE(row, rows.rend());
    EXPECT_LE(drawn.components_time_s, row->time_s + 1e-6);
    EXPECT_EQ(drawn.components, row->components);
    EXPECT_EQ(drawn.component_of, row->component_of);
    ASSERT_GE(drawn.timing_second, 0);
    if (replay) {
      EXPECT_EQ(drawn.timing_second, static_cast<long long>(std::floor(drawn.time_s)) - 1);
    }
    const auto& iterations = by_second[drawn.timing_second];
    ASSERT_FALSE(iterations.empty());
    double sum = 0, max_stf = 0;
    long long max_lag_ns = 0;
    for (const auto& [stf, lag_ns] : iterations) {
      sum += stf;
      max_stf = std::max(max_stf, stf);
      max_lag_ns = std::max(max_lag_ns, lag_ns);
    }
    // metrics.csv writes stf to 1e-6; the live feed has it unrounded.
    const double stf_tolerance = replay ? 1e-9 : 1e-6;
    EXPECT_EQ(drawn.iterations, static_cast<long long>(iterations.size()));
    EXPECT_NEAR(drawn.stf_mean, sum / static_cast<double>(iterations.size()), stf_tolerance);
    EXPECT_NEAR(drawn.stf_max, max_stf, stf_tolerance);
    EXPECT_NEAR(drawn.lag_max_ms, static_cast<double>(max_lag_ns) / 1e6, 1e-9);
  }
}

std::string ArtifactDir() {
  const char* build = std::getenv("SITLNET_BINARY_DIR");
  return std::string(build ? build : TempDir().c_str()) + "/tests/artifacts/view_browser";
}

// A socket of `type` bound to a free port of 127.0.0.1 (*port), or -1.
int LoopbackSocket(int type, int* port) {
  const int fd = socket(AF_INET, type | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    if (fd >= 0) close(fd);
    return -1;
  }
  *port = ntohs(address.sin_port);
  return fd;
}

// `sitlnet view DIR ARGS...` in the background, and the URL it prints.
struct ViewServer {
  // `url_end`: how the printed URL ends ("/" for a run, "/sweep.html" for a sweep's folder).
  explicit ViewServer(const std::string& dir, const std::string& url_end = "/")
      : child({integration_test::SitlnetBinary(), "view", dir, "--listen", "127.0.0.1:0"}) {
    if (child.WaitForOutput(false, url_end + "\n", 30 * kNsPerS)) {
      const size_t at = child.out().find("http://");
      if (at != std::string::npos) url = child.out().substr(at, child.out().find('\n') - at);
    }
  }
  integration_test::Child child;
  std::string url;
};

TEST(ViewBrowserTest, ReplayDrawsTheTrajectoriesAndListsALinksFramesAsTheLossFile) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE_SETUP_GROUP("browser", ChromiumMissing());
  SITLNET_REQUIRE(PlaywrightMissing());
  SITLNET_REQUIRE(NodeMavlinkMissing());
  std::string why;
  const std::string& dir = FlightFolder(&why);
  ASSERT_FALSE(dir.empty()) << why;
  // Issue 34, item 2: robot 0's frame at 3.0 s carries an ArduCopter HEARTBEAT in GUIDED,
  // encoded by node-mavlink and written apart from sitlnet's pcap writer.
  const CommandResult heartbeat = RunCommand({"node", NodeMavlinkDir() + "/append_heartbeat.cjs",
                                              dir + "/medium.pcap", "0", "3000000000", "GUIDED"});
  ASSERT_EQ(heartbeat.exit_code, 0) << heartbeat.err;
  ViewServer server(dir);
  ASSERT_FALSE(server.url.empty()) << server.child.out() << server.child.err();

  std::vector<std::string> argv = {"node", PlaywrightDir() + "/test/check_page.cjs", server.url,
                                   ArtifactDir()};
  argv.insert(argv.end(), kTimes.begin(), kTimes.end());
  const CommandResult page = RunCommand(argv, 120 * kNsPerS);
  ASSERT_EQ(page.exit_code, 0) << page.out << page.err;
  const PageFacts facts = ParsePage(page.out);
  EXPECT_TRUE(facts.errors.empty()) << page.out;
  EXPECT_EQ(facts.screenshots, static_cast<int>(kTimes.size()) + 1);

  // Each robot where trajectories.csv puts it at the slider's time, and moved by the slider.
  const std::string trajectories = integration_test::ReadAll(dir + "/trajectories.csv");
  ASSERT_EQ(facts.robots.size(), 3 * kTimes.size()) << page.out;
  ExpectDrawnWhereTrajectoriesSay(facts.robots, trajectories);
  for (int robot = 0; robot < 3; ++robot) {
    const DrawnRobot& before = facts.robots[robot];
    const DrawnRobot& after = facts.robots[3 + robot];
    EXPECT_GT(std::hypot(after.x_px - before.x_px, after.y_px - before.y_px), 5)
        << "robot " << robot << " did not move on the page";
  }
  // The robot table's mode: flockers have no autopilot ("none") until robot 0's HEARTBEAT.
  const std::map<std::string, std::string> modes = {
      {"2.0 0", "none"}, {"2.0 1", "none"}, {"3.5 0", "GUIDED"}, {"3.5 1", "none"}};
  for (const auto& [time_and_robot, mode] : modes) {
    EXPECT_EQ(facts.modes.count(time_and_robot) ? facts.modes.at(time_and_robot) : "(no row)", mode)
        << time_and_robot << "\n"
        << page.out;
  }
  ASSERT_EQ(facts.timelines.size(), kTimes.size()) << page.out;
  ExpectTimelineAsTheRunsFiles(facts.timelines, dir, /*replay=*/true);

  // The clicked link's list: losses.csv.gz's rows of that link (transmitter `from`, station
  // `station`) in the last whole second before the slider's time, in time order.
  const long long second = static_cast<long long>(std::floor(std::stod(kTimes.back()))) - 1;
  const long long from = facts.from, station = facts.station;
  const long long start_ns = facts.start_ns, end_ns = facts.end_ns;
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
  ASSERT_FALSE(expected.empty()) << "no losses.csv.gz row for link " << from << " -> " << station;
  EXPECT_EQ(facts.total, static_cast<long long>(expected.size()));
  ASSERT_EQ(facts.frame_rows.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(facts.frame_rows[i], expected[i].second);

  kill(server.child.pid(), SIGTERM);
  EXPECT_EQ(server.child.Wait(10 * kNsPerS), 0) << server.child.err();
}

// `sitlnet run --view` while the flight goes: the page drawn twice, then the run interrupted;
// what the page drew must be what the run then wrote (trajectories.csv, links.csv).
TEST(ViewBrowserTest, LiveViewDrawsTheRunningFlightAsItsTrajectoriesAndLinks) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE_SETUP_GROUP("browser", ChromiumMissing());
  SITLNET_REQUIRE(PlaywrightMissing());
  // Long enough never to end by itself: the test stops it once the page has been read.
  const RunScenario scenario = WriteScenario(
      8, kFlight,
      std::string(kObstacle) + "timing { duration_ms: 3600000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-live";
  integration_test::Child run({integration_test::SitlnetBinary(), "run", scenario.path, "--out",
                               out, "--no-progress", "--view", "127.0.0.1:0"});
  ASSERT_TRUE(run.WaitForOutput(true, "/\n", 30 * kNsPerS)) << run.err();
  const size_t at = run.err().find("live view at http://");
  ASSERT_NE(at, std::string::npos) << run.err();
  const std::string url = run.err().substr(at + 13, run.err().find('\n', at) - at - 13);

  const CommandResult page = RunCommand(
      {"node", PlaywrightDir() + "/test/check_page.cjs", "--live", url, ArtifactDir(), "2"},
      120 * kNsPerS);
  kill(run.pid(), SIGINT);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  ASSERT_EQ(page.exit_code, 0) << page.out << page.err;
  const PageFacts facts = ParsePage(page.out);
  // Errors after the page was read are the run's end (the server went with it).
  EXPECT_TRUE(facts.errors.empty()) << page.out;
  EXPECT_EQ(facts.screenshots, 2);

  ASSERT_EQ(facts.robots.size(), 6u) << page.out;
  EXPECT_NE(facts.robots[0].time_s, facts.robots[3].time_s);  // The page followed the run.
  ExpectDrawnWhereTrajectoriesSay(facts.robots,
                                  integration_test::ReadAll(out + "/trajectories.csv"));

  // The links drawn: links.csv's rows of the second shown, those between two robots.
  const std::string links = integration_test::ReadAll(out + "/links.csv");
  ASSERT_EQ(facts.live_links.size(), 2u);
  for (const auto& [second, drawn] : facts.live_links) {
    std::set<std::string> expected;
    std::istringstream rows(links);
    for (std::string row; std::getline(rows, row);) {
      long long row_second = -1;
      int from = -1, to = -1;
      unsigned long long frames = 0, delivered = 0;
      if (std::sscanf(row.c_str(), "%lld,%d,%d,%llu,%llu", &row_second, &from, &to, &frames,
                      &delivered) == 5 &&
          row_second == second && to >= 0 && to != from) {
        expected.insert(std::to_string(from) + "," + std::to_string(to) + "," +
                        std::to_string(frames) + "," + std::to_string(delivered));
      }
    }
    EXPECT_FALSE(expected.empty()) << "second " << second;
    EXPECT_EQ(drawn, expected) << "second " << second;
  }
  ASSERT_EQ(facts.timelines.size(), 2u) << page.out;
  ExpectTimelineAsTheRunsFiles(facts.timelines, out, /*replay=*/false);
  ExpectNothingLeft(scenario.name);
}

// The case study at its split (issue 47, item 5), served from a folder this test writes: no
// flight. At 1.0 s, scenarios/arrow_flocking.textproto's robots where a lockstep run with seed 1
// had them at 31.0 s (its trajectories.csv). At 0.0 s they are at their start; at 2.0 s at the
// corners that run reached (x -4 to 175.55 m, y -18.11 to 18.10 m), so the whole field is as
// large as that run's, drawn as small. A GCS relay heard two of them.
constexpr double kSplitTrack[3][4][2] = {
    {{0, -2}, {0, 2}, {-4, -2}, {-4, 2}},
    {{16.9453, -10.1694}, {16.9261, 10.1534}, {11.9357, -7.2417}, {11.7817, 7.1608}},
    {{175.5533, -18.1128}, {175.5533, 18.1031}, {175.5533, -18.1128}, {175.5533, 18.1031}}};
// summary.json's gcs_relay as runner/summary.cc writes it: uav1 an ArduCopter in GUIDED
// (COPTER_MODE 4, ardupilotmega.xml), armed, 90 frames heard and 10 missing; uav2 a PX4 in
// AUTO.LOITER (main mode 4, sub mode 3: px4_custom_mode.h), disarmed, none missing.
constexpr char kGcsSummary[] =
    R"({"scenario":"arrow","gcs_relay":{"endpoints":"udp:127.0.0.1:14550","vehicles":[)"
    R"({"system_id":1,"address":"10.77.0.1","robot":"uav1","messages":90,"sequence_gaps":10,)"
    R"("heartbeat":{"type":2,"autopilot":3,"base_mode":217,"custom_mode":4,"armed":true}},)"
    R"({"system_id":2,"address":"10.77.0.2","robot":"uav2","messages":50,"sequence_gaps":0,)"
    R"("heartbeat":{"type":2,"autopilot":12,"base_mode":29,"custom_mode":50593792,"armed":false}}]}})";

void WriteText(const std::string& path, const std::string& text, bool gzip = false) {
  if (!gzip) {
    std::ofstream(path, std::ios::binary) << text;
    return;
  }
  gzFile file = gzopen(path.c_str(), "wb");
  ASSERT_NE(file, nullptr) << path;
  gzwrite(file, text.data(), static_cast<unsigned>(text.size()));
  gzclose(file);
}

// A run folder of the case study (kSplitTrack): links of second 0, shown at 1.0 s, green along
// each side of the arrow (uav1-uav3, uav2-uav4) and red across it.
std::string WriteSplitFolder() {
  const std::string dir = TempDir() + "/view-case-study-split";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(integration_test::SourceDir() + "/scenarios/arrow_flocking.textproto",
                             dir + "/scenario.textproto");
  std::string trajectories = std::string(run_formats::kTrajectoryHeader) + "\n";
  for (int sample = 0; sample < 3; ++sample) {
    for (int robot = 0; robot < 4; ++robot) {
      char row[256];
      std::snprintf(row, sizeof row,
                    "%d.000,%d,%.4f,%.4f,10.0000,1.000000,0.000000,0.000000,0.000000,0.0000,0.0000,"
                    "0.0000,47.39774200,8.54559400,498.0000\n",
                    sample, robot, kSplitTrack[sample][robot][0], kSplitTrack[sample][robot][1]);
      trajectories += row;
    }
  }
  WriteText(dir + "/trajectories.csv", trajectories);
  std::string links = std::string(run_formats::kLinkHeader) + "\n";
  for (int from = 0; from < 4; ++from) {
    for (int to = 0; to < 4; ++to) {
      if (from == to) continue;
      const bool same_side = (from % 2) == (to % 2);  // uav1, uav3 south; uav2, uav4 north
      links += "0," + std::to_string(from) + "," + std::to_string(to) +
               (same_side ? ",10,10,1,none,0,6,\n" : ",10,0,0,below_threshold,10,6,\n");
    }
  }
  WriteText(dir + "/links.csv", links);
  WriteText(dir + "/losses.csv.gz", std::string(run_formats::kLossHeader) + "\n", /*gzip=*/true);
  WriteText(dir + "/connectivity.csv",
            "time_s,components,robot_0,robot_1,robot_2,robot_3\n0.100000,2,0,1,0,1\n");
  WriteText(dir + "/metrics.csv",
            "iteration,start_ns,t_phy_ns,t_net_ns,t_total_ns,t_overhead_ns,stf,lag_ns\n"
            "0,0,1,1,1,0,0.500000,0\n");
  WriteText(dir + "/summary.json", std::string(kGcsSummary) + "\n");
  return dir;
}

struct Box {
  double x = 0, y = 0, width = 0, height = 0;
};

// What check_map.cjs printed, by stage ("whole", "fit", "zoom", "pan").
struct MapFacts {
  std::vector<std::string> errors;
  std::map<std::string, std::vector<std::string>> gcs;  // Robot index -> its GCS columns.
  std::map<std::string, Box> views;                     // width, height in Box::width, height
  std::map<std::string, double> px_per_m;
  std::map<std::string, std::map<int, std::pair<double, double>>> robots;
  std::map<std::string, std::map<int, Box>> labels;
  std::map<std::string, std::vector<std::vector<double>>> links;  // from, to, x1, y1, x2, y2
  double anchor_x = 0, anchor_y = 0;
  std::string selected;
  int screenshots = 0;
};

MapFacts ParseMap(const std::string& out) {
  MapFacts facts;
  std::istringstream lines(out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string kind, stage;
    fields >> kind;
    if (kind == "console_error") facts.errors.push_back(line);
    if (kind == "gcs") {
      std::string robot;
      fields >> robot;
      for (std::string field; fields >> field;) facts.gcs[robot].push_back(field);
    }
    if (kind == "view") {
      Box box;
      double min_x = 0, max_y = 0;
      fields >> stage >> box.width >> box.height >> facts.px_per_m[stage] >> min_x >> max_y;
      facts.views[stage] = box;
    }
    if (kind == "robot") {
      int robot = -1;
      double x = 0, y = 0;
      fields >> stage >> robot >> x >> y;
      facts.robots[stage][robot] = {x, y};
    }
    if (kind == "label") {
      int robot = -1;
      Box box;
      fields >> stage >> robot >> box.x >> box.y >> box.width >> box.height;
      facts.labels[stage][robot] = box;
    }
    if (kind == "link") {
      fields >> stage;
      std::vector<double> link;
      for (double value; fields >> value;) link.push_back(value);
      facts.links[stage].push_back(link);
    }
    if (kind == "anchor") fields >> facts.anchor_x >> facts.anchor_y;
    if (kind == "selected") fields >> facts.selected;
    if (kind == "screenshot") ++facts.screenshots;
  }
  return facts;
}

bool Overlap(const Box& a, const Box& b) {
  return std::min(a.x + a.width, b.x + b.width) > std::max(a.x, b.x) &&
         std::min(a.y + a.height, b.y + b.height) > std::max(a.y, b.y);
}

TEST(ViewBrowserTest, TheCaseStudySplitShowsTheGcsColumnsLabelsApartAndZoomsPansAndFits) {
  SITLNET_REQUIRE_SETUP_GROUP("browser", ChromiumMissing());
  SITLNET_REQUIRE(PlaywrightMissing());
  const std::string dir = WriteSplitFolder();
  ViewServer server(dir);
  ASSERT_FALSE(server.url.empty()) << server.child.out() << server.child.err();
  const CommandResult page = RunCommand(
      {"node", PlaywrightDir() + "/test/check_map.cjs", server.url, ArtifactDir(), "1.0"},
      60 * kNsPerS);
  kill(server.child.pid(), SIGTERM);
  EXPECT_EQ(server.child.Wait(10 * kNsPerS), 0) << server.child.err();
  ASSERT_EQ(page.exit_code, 0) << page.out << page.err;
  const MapFacts facts = ParseMap(page.out);
  EXPECT_TRUE(facts.errors.empty()) << page.out;
  EXPECT_EQ(facts.screenshots, 4);

  // The robot table: system id, GCS mode, armed, loss = gaps / (heard + gaps).
  using Row = std::vector<std::string>;
  EXPECT_EQ(facts.gcs.at("0"), (Row{"1", "GUIDED", "true", "0.1"})) << page.out;
  EXPECT_EQ(facts.gcs.at("1"), (Row{"2", "AUTO.LOITER", "false", "0"})) << page.out;
  EXPECT_EQ(facts.gcs.at("2"), (Row{"-", "-", "-", "-"})) << page.out;
  EXPECT_EQ(facts.gcs.at("3"), (Row{"-", "-", "-", "-"})) << page.out;

  for (const char* stage : {"whole", "fit", "zoom", "pan"}) {
    SCOPED_TRACE(stage);
    // No two labels' boxes overlap.
    const std::map<int, Box>& labels = facts.labels.at(stage);
    ASSERT_EQ(labels.size(), 4u) << page.out;
    for (auto a = labels.begin(); a != labels.end(); ++a) {
      for (auto b = std::next(a); b != labels.end(); ++b) {
        EXPECT_FALSE(Overlap(a->second, b->second))
            << "labels of robots " << a->first << " and " << b->first << "\n"
            << page.out;
      }
    }
    // Each link drawn from its robot to the other, kLinkOffsetPx (2.5 px) to its right.
    const auto& robots = facts.robots.at(stage);
    ASSERT_EQ(facts.links.at(stage).size(), 12u) << page.out;
    for (const std::vector<double>& link : facts.links.at(stage)) {
      ASSERT_EQ(link.size(), 6u);
      const auto [fx, fy] = robots.at(static_cast<int>(link[0]));
      const auto [tx, ty] = robots.at(static_cast<int>(link[1]));
      EXPECT_NEAR(std::hypot(link[2] - fx, link[3] - fy), 2.5, 0.6) << page.out;
      EXPECT_NEAR(std::hypot(link[4] - tx, link[5] - ty), 2.5, 0.6) << page.out;
    }
  }
  // Fit the fleet: every robot inside the map, the fleet larger than on the whole field and at
  // least half the map across.
  const Box& view = facts.views.at("fit");
  double min_x = 1e9, max_x = -1e9, min_y = 1e9, max_y = -1e9;
  for (const auto& [robot, centre] : facts.robots.at("fit")) {
    EXPECT_GT(centre.first, 0);
    EXPECT_LT(centre.first, view.width);
    EXPECT_GT(centre.second, 0);
    EXPECT_LT(centre.second, view.height);
    min_x = std::min(min_x, centre.first);
    max_x = std::max(max_x, centre.first);
    min_y = std::min(min_y, centre.second);
    max_y = std::max(max_y, centre.second);
  }
  EXPECT_GT(facts.px_per_m.at("fit"), facts.px_per_m.at("whole")) << page.out;
  EXPECT_TRUE(max_x - min_x > view.width / 2 || max_y - min_y > view.height / 2) << page.out;
  // The wheel zoomed in about robot 0, which stayed under the pointer; the others moved away
  // from it by the scale's ratio.
  const double zoom = facts.px_per_m.at("zoom") / facts.px_per_m.at("fit");
  EXPECT_GT(zoom, 1.2);
  const auto& fit = facts.robots.at("fit");
  const auto& zoomed = facts.robots.at("zoom");
  EXPECT_NEAR(zoomed.at(0).first, facts.anchor_x, 1.0);
  EXPECT_NEAR(zoomed.at(0).second, facts.anchor_y, 1.0);
  for (int robot = 1; robot < 4; ++robot) {
    EXPECT_NEAR(zoomed.at(robot).first - facts.anchor_x,
                zoom * (fit.at(robot).first - facts.anchor_x), 1.0);
    EXPECT_NEAR(zoomed.at(robot).second - facts.anchor_y,
                zoom * (fit.at(robot).second - facts.anchor_y), 1.0);
  }
  // The drag moved every robot with the pointer, and selected no link.
  for (int robot = 0; robot < 4; ++robot) {
    EXPECT_NEAR(facts.robots.at("pan").at(robot).first, zoomed.at(robot).first + 60, 1.0);
    EXPECT_NEAR(facts.robots.at("pan").at(robot).second, zoomed.at(robot).second + 40, 1.0);
  }
  EXPECT_EQ(facts.selected, "-");
}

// `sitlnet run --view` with a GCS relay (issue 47, item 5): a ground station and two of sitlnet's
// test autopilots, which send it HEARTBEATs once armed (MAV_AUTOPILOT_GENERIC, custom mode 0,
// MAV_MODE_FLAG_SAFETY_ARMED) with system id = robot index + 1. The page must show each vehicle in
// its own robot's row: the relay names the robot by the address its frames came from.
TEST(ViewBrowserTest, TheLiveViewShowsEachRelayedVehicleInItsRobotsRow) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE_SETUP_GROUP("browser", ChromiumMissing());
  SITLNET_REQUIRE(PlaywrightMissing());
  constexpr int kSlot = 9;
  const RunScenario scenario = WriteScenario(
      kSlot, RelayFleetRobots(kSlot), "timing { duration_ms: 3600000 pacing: PACING_LOCKSTEP }\n");
  DownGuard guard(scenario.name);
  // A GCS port that takes the relay's datagrams and reads none.
  int gcs_port = 0;
  const int gcs = LoopbackSocket(SOCK_DGRAM, &gcs_port);
  ASSERT_GE(gcs, 0);
  const std::string out = TempDir() + "/" + scenario.name + "-live-gcs";
  integration_test::Child run({integration_test::SitlnetBinary(), "run", scenario.path, "--out",
                               out, "--no-progress", "--view", "127.0.0.1:0", "--gcs",
                               "udp:127.0.0.1:" + std::to_string(gcs_port)});
  ASSERT_TRUE(run.WaitForOutput(true, "/\n", 30 * kNsPerS)) << run.err();
  const size_t at = run.err().find("live view at http://");
  ASSERT_NE(at, std::string::npos) << run.err();
  const std::string url = run.err().substr(at + 13, run.err().find('\n', at) - at - 13);

  const CommandResult page =
      RunCommand({"node", PlaywrightDir() + "/test/check_live_gcs.cjs", url, ArtifactDir(), "2"},
                 90 * kNsPerS);
  kill(run.pid(), SIGINT);
  EXPECT_EQ(run.Wait(60 * kNsPerS), 130) << run.err();
  close(gcs);
  ASSERT_EQ(page.exit_code, 0) << page.out << page.err;
  EXPECT_EQ(page.out.find("console_error"), std::string::npos) << page.out;
  std::map<std::string, std::vector<std::string>> rows;
  std::map<std::string, std::string> statuses;
  std::istringstream lines(page.out);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream fields(line);
    std::string kind, robot;
    fields >> kind >> robot;
    if (kind == "gcs") {
      for (std::string field; fields >> field;) rows[robot].push_back(field);
    }
    if (kind == "status") std::getline(fields >> std::ws, statuses[robot]);
  }
  using Row = std::vector<std::string>;
  EXPECT_EQ(rows["0"], (Row{"-", "-", "-", "-"})) << page.out;  // The station sent nothing.
  for (const auto& [robot, system_id] : {std::pair{"1", "2"}, std::pair{"2", "3"}}) {
    ASSERT_EQ(rows[robot].size(), 4u) << page.out;
    EXPECT_EQ(rows[robot][0], system_id) << page.out;
    EXPECT_EQ(rows[robot][1], "custom_mode_0") << page.out;
    EXPECT_EQ(rows[robot][2], "true") << page.out;
    const double loss = std::stod(rows[robot][3]);
    EXPECT_GE(loss, 0);
    EXPECT_LE(loss, 1);
    EXPECT_EQ(statuses[robot].rfind("custom mode 0 · armed · ", 0), 0u) << statuses[robot];
  }
  EXPECT_EQ(statuses["0"], "");
  ExpectNothingLeft(scenario.name);
}

// The refusals are one line each, before anything is served.
TEST(ViewBrowserTest, APortInUseANonLocalAddressAndAnIncompleteFolderAreOneLine) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  std::string why;
  const std::string& dir = FlightFolder(&why);
  ASSERT_FALSE(dir.empty()) << why;
  const std::string sitlnet = integration_test::SitlnetBinary();

  int taken_port = 0;
  const int taken = LoopbackSocket(SOCK_STREAM, &taken_port);
  ASSERT_GE(taken, 0);
  ASSERT_EQ(listen(taken, 1), 0);
  const std::string in_use = "127.0.0.1:" + std::to_string(taken_port);
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

// Issue 48, item 2: `sitlnet view SWEEP_DIR` shows a real sweep (2 flockers, 1 s each).
// A 2 x 2 sweep over two fields, 2 seeds, one point made to fail. Oracle: the sweep's own
// summary.csv: each metric is plotted against each field, one line per value of the other field,
// a mark per row with its mean and half-width (none for the failed point's combination, n = 1);
// points.csv's failed row is marked.
TEST(ViewBrowserTest, ASweepsPagePlotsEachMetricsMeanAndIntervalAsSummaryCsvHoldsThem) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  SITLNET_REQUIRE_SETUP_GROUP("browser", ChromiumMissing());
  SITLNET_REQUIRE(PlaywrightMissing());
  const RunScenario scenario = WriteScenario(
      9,
      "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"flocker\" "
      "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
      "robot { name: \"b\" position_m { x: 0 y: 6 z: 0.2 } image: \"flocker\" "
      "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n",
      "timing { duration_ms: 1000 pacing: PACING_LOCKSTEP }\n");
  const std::string out = TempDir() + "/" + scenario.name + "-sweep";
  const std::vector<std::string> fields = {"radio.rate_mbps", "robot[1].position_m.y"};
  RunCommand({"rm", "-rf", out});
  // The point made to fail: a run folder that others can write is refused by `sitlnet run`.
  const std::string failing = out + "/radio.rate_mbps=54,robot[1].position_m.y=20,seed=2";
  ASSERT_EQ(RunCommand({"mkdir", "-p", failing}).exit_code, 0);
  ASSERT_EQ(chmod(failing.c_str(), 0777), 0);
  const CommandResult sweep = RunCommand(
      {integration_test::SitlnetBinary(), "sweep", scenario.path, "--seeds", "1-2", "--set",
       fields[0] + "=6,54", "--set", fields[1] + "=6,20", "--jobs", "2", "--out", out},
      120 * kNsPerS);
  ASSERT_EQ(sweep.exit_code, 1) << sweep.err;  // The failed point.
  ViewServer server(out, "/sweep.html");
  ASSERT_FALSE(server.url.empty()) << server.child.out() << server.child.err();
  const CommandResult page = RunCommand(
      {"node", PlaywrightDir() + "/test/check_sweep.cjs", server.url, ArtifactDir()},
      60 * kNsPerS);
  kill(server.child.pid(), SIGTERM);
  EXPECT_EQ(server.child.Wait(10 * kNsPerS), 0) << server.child.err();
  ASSERT_EQ(page.exit_code, 0) << page.out << page.err;
  EXPECT_EQ(page.out.find("console_error"), std::string::npos) << page.out;

  // summary.csv: radio.rate_mbps,robot[1].position_m.y,metric,n,mean,sd,ci95_half_width. The
  // marks expected: "METRIC FIELD LABEL X" -> "MEAN HALF", LABEL the other field's value.
  std::map<std::string, std::pair<double, double>> expected;
  std::set<std::string> metrics_with_mean;
  std::istringstream summary(ReadAll(out + "/summary.csv"));
  std::string line;
  int summary_rows = 0, single_point_rows = 0;
  std::getline(summary, line);
  while (std::getline(summary, line)) {
    ++summary_rows;
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    cells.resize(7);
    if (cells[0] == "54" && cells[1] == "20") single_point_rows += cells[3] == "1";
    if (cells[4].empty()) continue;
    metrics_with_mean.insert(cells[2]);
    const std::pair<double, double> mark = {std::stod(cells[4]),
                                            cells[6].empty() ? 0 : std::stod(cells[6])};
    expected[cells[2] + " " + fields[0] + " " + fields[1] + "=" + cells[1] + " " + cells[0]] = mark;
    expected[cells[2] + " " + fields[1] + " " + fields[0] + "=" + cells[0] + " " + cells[1]] = mark;
  }
  EXPECT_GT(single_point_rows, 0) << "the failed point's combination has one point";
  ASSERT_FALSE(expected.empty()) << "no metric with a mean in summary.csv";
  std::map<std::string, std::pair<double, double>> drawn;
  std::set<std::string> plots;
  std::istringstream facts(page.out);
  while (std::getline(facts, line)) {
    std::istringstream words(line);
    std::string kind, metric, field;
    words >> kind >> metric >> field;
    if (kind == "plot") {
      int lines = 0;
      words >> lines;
      plots.insert(metric + " " + field);
      EXPECT_EQ(lines, 2) << line;  // One per value of the other field.
    }
    if (kind == "mark") {
      std::string x, mean, half, label;
      words >> x >> mean >> half >> label;
      drawn[metric + " " + field + " " + label + " " + x] = {std::stod(mean), std::stod(half)};
    }
  }
  EXPECT_EQ(plots.size(), 2 * metrics_with_mean.size()) << page.out;
  EXPECT_EQ(plots.count("delivery.obstructed.ratio radio.rate_mbps"), 0u) << page.out;
  ASSERT_EQ(drawn.size(), expected.size()) << page.out;
  for (const auto& [key, mark] : expected) {
    SCOPED_TRACE(key);
    ASSERT_EQ(drawn.count(key), 1u) << page.out;
    EXPECT_DOUBLE_EQ(drawn[key].first, mark.first);
    EXPECT_DOUBLE_EQ(drawn[key].second, mark.second);
  }
  EXPECT_NE(page.out.find("table summary " + std::to_string(summary_rows) + " 7\n"),
            std::string::npos)
      << page.out;
  EXPECT_NE(page.out.find("table points 8 "), std::string::npos) << page.out;
  EXPECT_NE(page.out.find("failed_rows 1\n"), std::string::npos) << page.out;
  if (!::testing::Test::HasFailure()) RunCommand({"rm", "-rf", out});
}

}  // namespace
}  // namespace sitlnet::nns::testing
