// The sweep's tables, one row per point and one per combination and metric (a long table, which
// gnuplot, pandas and R read without reshaping).
#include "sweep/results_csv.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "common/common.h"

namespace sitlnet::sweep {
namespace {

// RFC 4180: a field with a comma, quote or newline is quoted, its quotes doubled.
std::string CsvField(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// %.10g; empty for a missing or undefined number.
std::string Number(std::optional<double> value) {
  if (!value || !std::isfinite(*value)) return "";
  char text[32];
  std::snprintf(text, sizeof text, "%.10g", *value);
  return text;
}

const char* StatusName(PointState::Status status) {
  switch (status) {
    case PointState::kFinished:
      return "ok";
    case PointState::kFailed:
      return "failed";
    case PointState::kNotRun:
      return "not_run";
  }
  return "";
}

}  // namespace

void WriteWholeFile(const std::string& path, const std::string& text) {
  const UniqueFd fd(open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644));
  if (!fd.valid()) throw Error(SystemErrorMessage("create \"" + path + "\"", errno));
  for (size_t done = 0; done < text.size();) {
    const ssize_t n = write(fd.get(), text.data() + done, text.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) throw Error(SystemErrorMessage("write \"" + path + "\"", errno));
    done += static_cast<size_t>(n);
  }
}

PointState ReadPointState(const std::string& folder, const std::vector<std::string>& metrics) {
  PointState state;
  const std::optional<google::protobuf::Struct> summary = ReadSummaryJson(folder + "/summary.json");
  if (summary && IsFinishedSummary(*summary)) {
    state.status = PointState::kFinished;
    for (const std::string& metric : metrics) state.metrics.push_back(SummaryMetric(*summary, metric));
    return state;
  }
  std::ifstream failure(folder + "/" + kFailureFile);
  if (failure && std::getline(failure, state.reason)) state.status = PointState::kFailed;
  state.metrics.resize(metrics.size());
  return state;
}

void WriteResults(const std::string& out_dir, const std::vector<SweepAxis>& axes,
                  const std::vector<SweepPoint>& points, const std::vector<PointState>& states,
                  const std::vector<std::string>& metrics) {
  std::string axes_header;
  for (const SweepAxis& axis : axes) axes_header += CsvField(axis.field_path) + ",";

  std::string table = "point," + axes_header + "seed,status,reason";
  for (const std::string& metric : metrics) table += "," + CsvField(metric);
  table += "\n";
  for (size_t p = 0; p < points.size(); ++p) {
    table += CsvField(points[p].folder) + ",";
    for (const std::string& value : points[p].values) table += CsvField(value) + ",";
    table += std::to_string(points[p].seed) + "," + StatusName(states[p].status) + "," +
             CsvField(states[p].reason);
    for (const std::optional<double>& value : states[p].metrics) table += "," + Number(value);
    table += "\n";
  }
  WriteWholeFile(out_dir + "/points.csv", table);

  std::string summary = axes_header + "metric,n,mean,sd,ci95_half_width\n";
  for (const CombinationSummary& row : SummarizeCombinations(points, states, metrics.size())) {
    for (const std::string& value : points[row.first_point].values) summary += CsvField(value) + ",";
    summary += CsvField(metrics[row.metric]) + "," + std::to_string(row.stats.n) + "," +
               Number(row.stats.mean) + "," + Number(row.stats.standard_deviation) + "," +
               Number(row.stats.ci95_half_width) + "\n";
  }
  WriteWholeFile(out_dir + "/summary.csv", summary);
}

std::vector<CombinationSummary> SummarizeCombinations(const std::vector<SweepPoint>& points,
                                                      const std::vector<PointState>& states,
                                                      size_t metrics) {
  std::vector<CombinationSummary> rows;
  for (size_t first = 0; first < points.size();) {
    size_t end = first;
    while (end < points.size() && points[end].combination == points[first].combination) ++end;
    for (size_t m = 0; m < metrics; ++m) {
      std::vector<double> samples;
      for (size_t p = first; p < end; ++p) {
        if (states[p].metrics[m]) samples.push_back(*states[p].metrics[m]);
      }
      rows.push_back({first, m, Summarize(samples)});
    }
    first = end;
  }
  return rows;
}

}  // namespace sitlnet::sweep
