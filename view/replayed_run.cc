#include "view/replayed_run.h"

#include <sys/stat.h>
#include <zlib.h>

#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <sstream>

#include "coordinator/metrics.h"
#include "run_formats/run_formats.h"

namespace sitlnet::view {
namespace {

std::vector<std::string> SplitCells(const std::string& line) {
  std::vector<std::string> cells;
  size_t start = 0;
  while (true) {
    const size_t comma = line.find(',', start);
    cells.push_back(line.substr(start, comma - start));
    if (comma == std::string::npos) return cells;
    start = comma + 1;
  }
}

// The rows of a CSV file after its header, which must be `header`. `read_line` gives the
// next line (without '\n') or false at the end.
class CsvReader {
 public:
  CsvReader(std::string path, const char* header, std::function<bool(std::string*)> read_line)
      : path_(std::move(path)), read_line_(std::move(read_line)) {
    std::string first;
    if (!read_line_(&first)) throw Error(path_ + ": empty (the run did not finish writing it)");
    line_number_ = 1;
    if (first != header) {
      throw Error(path_ + ":1: header is not \"" + header +
                  "\" (a run folder of another sitlnet version)");
    }
  }

  // The next row's cells, at least `columns` of them; false at the end.
  bool Next(size_t columns, std::vector<std::string>* cells) {
    std::string line;
    if (!read_line_(&line)) return false;
    ++line_number_;
    *cells = SplitCells(line);
    if (cells->size() != columns) {
      Fail(std::to_string(cells->size()) + " fields, not " + std::to_string(columns));
    }
    return true;
  }

  template <typename Number>
  Number Parse(const std::string& cell, const char* column) const {
    Number value{};
    const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
    if (cell.empty() || error != std::errc() || end != cell.data() + cell.size()) {
      Fail(std::string(column) + " \"" + cell + "\" is not a number");
    }
    return value;
  }

  [[noreturn]] void Fail(const std::string& what) const {
    throw Error(path_ + ":" + std::to_string(line_number_) + ": " + what);
  }

 private:
  std::string path_;
  std::function<bool(std::string*)> read_line_;
  int line_number_ = 0;
};

std::string RequireFile(const std::string& run_dir, const std::string& name, const char* why) {
  const std::string path = run_dir + "/" + name;
  struct stat info {};
  if (stat(path.c_str(), &info) != 0 || !S_ISREG(info.st_mode)) {
    throw Error("run folder \"" + run_dir + "\" is incomplete: no " + name + " (" + why + ")");
  }
  return path;
}

void ReadTrajectories(const std::string& path, ReplayedRun* record) {
  std::istringstream text(ReadText(path));
  CsvReader csv(path, run_formats::kTrajectoryHeader,
                [&](std::string* line) { return static_cast<bool>(std::getline(text, *line)); });
  const int robots = static_cast<int>(record->scenario.robots.size());
  std::vector<std::string> cells;
  while (csv.Next(15, &cells)) {
    PoseSample pose;
    pose.time_ns = static_cast<TimeNs>(csv.Parse<double>(cells[0], "time_s") * 1e3 + 0.5) *
                   kNsPerMs;  // Written with millisecond precision.
    pose.robot = csv.Parse<int>(cells[1], "robot");
    if (pose.robot < 0 || pose.robot >= robots) {
      csv.Fail("robot " + cells[1] + " is not in scenario.textproto");
    }
    pose.x_m = csv.Parse<double>(cells[2], "x_m");
    pose.y_m = csv.Parse<double>(cells[3], "y_m");
    pose.z_m = csv.Parse<double>(cells[4], "z_m");
    pose.vx_m_s = csv.Parse<double>(cells[9], "vx_m_s");
    pose.vy_m_s = csv.Parse<double>(cells[10], "vy_m_s");
    pose.vz_m_s = csv.Parse<double>(cells[11], "vz_m_s");
    record->poses.push_back(pose);
  }
}

// links.csv as written before it named each link's rate and MCS (issue 44): still read.
constexpr char kLinkHeaderWithoutRates[] =
    "second,from,to,frames,delivered,delivery_ratio,main_cause,main_cause_frames";

void ReadLinks(const std::string& path, ReplayedRun* record) {
  const std::string whole = ReadText(path);
  const bool with_rates = whole.compare(0, whole.find('\n'), kLinkHeaderWithoutRates) != 0;
  std::istringstream text(whole);
  CsvReader csv(path, with_rates ? run_formats::kLinkHeader : kLinkHeaderWithoutRates,
                [&](std::string* line) { return static_cast<bool>(std::getline(text, *line)); });
  std::vector<std::string> cells;
  while (csv.Next(with_rates ? 10 : 8, &cells)) {
    LinkSecond link;
    link.second = csv.Parse<int>(cells[0], "second");
    link.from = csv.Parse<int>(cells[1], "from");
    link.to = csv.Parse<int>(cells[2], "to");
    link.frames = csv.Parse<int>(cells[3], "frames");
    link.delivered = csv.Parse<int>(cells[4], "delivered");
    if (!cells[5].empty()) link.delivery_ratio = csv.Parse<double>(cells[5], "delivery_ratio");
    link.main_cause = cells[6];
    link.main_cause_frames = csv.Parse<int>(cells[7], "main_cause_frames");
    if (with_rates) {
      link.rate_mbps = csv.Parse<double>(cells[8], "rate_mbps");
      if (!cells[9].empty()) link.mcs = csv.Parse<int>(cells[9], "mcs");
    }
    record->links.push_back(link);
  }
}

void ReadConnectivity(const std::string& path, ReplayedRun* record) {
  std::istringstream text(ReadText(path));
  const size_t robots = record->scenario.robots.size();
  std::string header = "time_s,components";
  for (size_t i = 0; i < robots; ++i) header += ",robot_" + std::to_string(i);
  CsvReader csv(path, header.c_str(),
                [&](std::string* line) { return static_cast<bool>(std::getline(text, *line)); });
  std::vector<std::string> cells;
  std::vector<int> component_of(robots);
  while (csv.Next(2 + robots, &cells)) {
    // Written with microsecond precision (std::to_string of seconds).
    const TimeNs time_ns =
        std::llround(csv.Parse<double>(cells[0], "time_s") * 1e6) * (kNsPerS / 1000000);
    for (size_t i = 0; i < robots; ++i) component_of[i] = csv.Parse<int>(cells[2 + i], "robot");
    AppendIfChanged(time_ns, csv.Parse<int>(cells[1], "components"), component_of,
                    &record->connectivity);
  }
}

void ReadMetrics(const std::string& path, ReplayedRun* record) {
  std::istringstream text(ReadText(path));
  std::string header = coordinator::MetricsCsvWriter::Header();
  header.pop_back();  // Its '\n'.
  CsvReader csv(path, header.c_str(),
                [&](std::string* line) { return static_cast<bool>(std::getline(text, *line)); });
  std::vector<std::string> cells;
  run_formats::SecondTimingAccumulator seconds;
  const auto keep = [&](std::optional<run_formats::SecondTiming> second) {
    if (second) record->timing.push_back(*second);
  };
  while (csv.Next(8, &cells)) {
    keep(seconds.Add(csv.Parse<TimeNs>(cells[1], "start_ns"), csv.Parse<double>(cells[6], "stf"),
                     csv.Parse<TimeNs>(cells[7], "lag_ns")));
  }
  keep(seconds.Finish());
}

void ReadLosses(const std::string& path, ReplayedRun* record) {
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) throw Error(SystemErrorMessage("open \"" + path + "\"", errno));
  std::unique_ptr<gzFile_s, int (*)(gzFile)> closer(file, gzclose);
  char buffer[4096];
  const auto read_line = [&](std::string* line) {
    line->clear();
    while (gzgets(file, buffer, sizeof buffer) != nullptr) {
      line->append(buffer);
      if (line->back() == '\n') {
        line->pop_back();
        return true;
      }
    }
    int error = Z_OK;
    const char* message = gzerror(file, &error);
    if (error != Z_OK && error != Z_BUF_ERROR) throw Error(path + ": " + message);
    return !line->empty();
  };
  CsvReader csv(path, run_formats::kLossHeader, read_line);
  LossRow row;
  while (csv.Next(13, &row.cells)) {
    row.time_ns = csv.Parse<TimeNs>(row.cells[0], "time_ns");
    row.from = csv.Parse<int>(row.cells[1], "from");
    row.station = csv.Parse<int>(row.cells[6], "station");
    record->losses_by_link[{row.from, row.station}].push_back(record->losses.size());
    record->losses.push_back(row);
  }
}

}  // namespace

std::string ReadText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(SystemErrorMessage("open \"" + path + "\"", errno));
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

ReplayedRun LoadReplayedRun(const std::string& run_dir) {
  ReplayedRun record;
  record.run_dir = run_dir;
  struct stat info {};
  if (stat(run_dir.c_str(), &info) != 0) {
    throw Error(SystemErrorMessage("run folder \"" + run_dir + "\"", errno));
  }
  if (!S_ISDIR(info.st_mode)) throw Error("run folder \"" + run_dir + "\" is not a folder");
  const char* unfinished = "the run did not finish";
  const std::string summary = RequireFile(run_dir, "summary.json", unfinished);
  const std::string scenario = RequireFile(run_dir, "scenario.textproto", unfinished);
  const std::string trajectories = RequireFile(run_dir, "trajectories.csv", unfinished);
  const std::string connectivity = RequireFile(run_dir, "connectivity.csv", unfinished);
  const std::string metrics = RequireFile(run_dir, "metrics.csv", unfinished);
  const char* no_losses =
      "a run of an older sitlnet, or one with --no-losses or --remote network";
  const std::string links = RequireFile(run_dir, "links.csv", no_losses);
  const std::string losses = RequireFile(run_dir, "losses.csv.gz", no_losses);

  record.summary_json = ReadText(summary);
  if (record.summary_json.empty() || record.summary_json.front() != '{') {
    throw Error(summary + ": not a JSON object (the run did not finish writing it)");
  }
  record.scenario = LoadScenarioFile(scenario);
  ReadTrajectories(trajectories, &record);
  ReadConnectivity(connectivity, &record);
  ReadMetrics(metrics, &record);
  ReadLinks(links, &record);
  ReadLosses(losses, &record);
  record.modes =
      ReadAirModes(run_dir + "/medium.pcap", static_cast<int>(record.scenario.robots.size()));
  return record;
}

}  // namespace sitlnet::view
