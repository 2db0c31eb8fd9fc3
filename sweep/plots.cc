// The sweep's plots: each metric against each swept field, with 95 % interval bars (gnuplot, as
// `sitlnet run`'s plots). The numbers go into the script as data blocks, so gnuplot reads no file
// and no value of the user's is parsed as a command (GnuplotQuoted).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/common.h"
#include "sweep/results_csv.h"

namespace sitlnet::sweep {
namespace {

// A file-name part: letters and digits kept, anything else '_'.
std::string FileNamePart(const std::string& text) {
  std::string part;
  for (char c : text) part += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return part;
}

bool AllNumbers(const std::vector<std::string>& values) {
  for (const std::string& value : values) {
    char* end = nullptr;
    std::strtod(value.c_str(), &end);
    if (value.empty() || end != value.c_str() + value.size()) return false;
  }
  return true;
}

// The plot of `metric` against axis `a`: one data block and one line per combination of the other
// axes' values (in the grid's order; axes of one value name no line), each point its x, mean and
// interval half-width.
std::string OnePlot(size_t plot_index, size_t a, size_t metric, const std::vector<SweepAxis>& axes,
                    const std::vector<SweepPoint>& points,
                    const std::vector<CombinationSummary>& rows, const std::string& metric_name,
                    const std::string& png) {
  const bool numeric = AllNumbers(axes[a].values);
  std::map<std::string, size_t> value_index;
  for (size_t i = 0; i < axes[a].values.size(); ++i) value_index[axes[a].values[i]] = i;
  std::vector<std::string> labels;  // Per line, in first-seen order.
  // Per line label: (x, its data row), drawn in ascending x so that the line does not zig-zag.
  std::map<std::string, std::vector<std::pair<double, std::string>>> data;
  for (const CombinationSummary& row : rows) {
    if (row.metric != metric || row.stats.n == 0 || !std::isfinite(row.stats.mean)) continue;
    const std::vector<std::string>& values = points[row.first_point].values;
    std::string label;
    for (size_t other = 0; other < axes.size(); ++other) {
      if (other == a || axes[other].values.size() < 2) continue;  // the same on every line
      label += (label.empty() ? "" : ", ") + axes[other].field_path + "=" + values[other];
    }
    if (data.find(label) == data.end()) labels.push_back(label);
    const double half_width = std::isfinite(row.stats.ci95_half_width) ? row.stats.ci95_half_width : 0;
    const double x = numeric ? std::strtod(values[a].c_str(), nullptr)
                             : static_cast<double>(value_index[values[a]]);
    char numbers[64];
    std::snprintf(numbers, sizeof numbers, " %.10g %.10g\n", row.stats.mean, half_width);
    data[label].emplace_back(
        x, (numeric ? values[a] : std::to_string(value_index[values[a]])) + numbers);
  }
  if (labels.empty()) return "";
  std::ostringstream script;
  for (size_t line = 0; line < labels.size(); ++line) {
    std::vector<std::pair<double, std::string>>& rows_of_line = data[labels[line]];
    std::stable_sort(rows_of_line.begin(), rows_of_line.end(),
                     [](const auto& p, const auto& q) { return p.first < q.first; });
    script << "$p" << plot_index << "_" << line << " << EOD\n";
    for (const auto& [x, text] : rows_of_line) script << text;
    script << "EOD\n";
  }
  script << "set output " << GnuplotQuoted(png) << "\n"
         << "set title " << GnuplotQuoted(metric_name + " against " + axes[a].field_path +
                                          " (mean, 95 % interval)")
         << "\nset xlabel " << GnuplotQuoted(axes[a].field_path) << "\nset ylabel "
         << GnuplotQuoted(metric_name) << "\n";
  if (numeric) {
    script << "set xtics autofreq\nset offsets graph 0.05, graph 0.05, 0, 0\n";
  } else {
    script << "set xtics (";
    for (size_t i = 0; i < axes[a].values.size(); ++i) {
      script << (i ? ", " : "") << GnuplotQuoted(axes[a].values[i]) << " " << i;
    }
    script << ")\nset offsets 0.5, 0.5, 0, 0\n";
  }
  script << "plot ";
  for (size_t line = 0; line < labels.size(); ++line) {
    script << (line ? ", " : "") << "$p" << plot_index << "_" << line
           << " using 1:2:3 with yerrorlines pt 7 title "
           << GnuplotQuoted(labels[line].empty() ? metric_name : labels[line]);
  }
  script << "\n";
  return script.str();
}

}  // namespace

std::vector<std::string> DrawPlots(const std::string& out_dir, const std::vector<SweepAxis>& axes,
                                   const std::vector<SweepPoint>& points,
                                   const std::vector<CombinationSummary>& rows,
                                   const std::vector<std::string>& metrics, std::string* warning) {
  std::ostringstream script;
  // noenhanced: field names' underscores are text, not subscripts.
  script << "set terminal pngcairo noenhanced size 900,600 font 'sans,10'\nset key below\n";
  std::vector<std::string> pngs;
  try {
    for (size_t a = 0; a < axes.size(); ++a) {
      if (axes[a].values.size() < 2) continue;
      for (size_t m = 0; m < metrics.size(); ++m) {
        const std::string png =
            "plot_" + FileNamePart(metrics[m]) + "_vs_" + FileNamePart(axes[a].field_path) + ".png";
        const std::string plot_script =
            OnePlot(pngs.size(), a, m, axes, points, rows, metrics[m], png);
        if (plot_script.empty()) continue;
        script << plot_script;
        pngs.push_back(out_dir + "/" + png);
      }
    }
  } catch (const Error& error) {
    *warning = std::string("no plots: ") + error.what();
    return {};
  }
  if (pngs.empty()) return {};
  try {
    WriteWholeFile(out_dir + "/plots.gnuplot", script.str());
  } catch (const Error& error) {
    *warning = error.what();
  }
  const std::string failure = RunGnuplot(script.str(), out_dir, out_dir + "/plots.log");
  if (!failure.empty()) {
    *warning = failure;
    return {};
  }
  return pngs;
}

}  // namespace sitlnet::sweep
