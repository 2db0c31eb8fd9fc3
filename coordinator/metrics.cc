#include "coordinator/metrics.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>

namespace sitlnet::coordinator {

void CompleteMetrics(TimeNs iteration_ns, IterationMetrics* m) {
  m->t_overhead_ns = m->t_total_ns - std::max(m->t_phy_ns, m->t_net_ns);
  m->stf = static_cast<double>(m->t_total_ns) / static_cast<double>(iteration_ns);
}

const char* MetricsCsvWriter::Header() {
  return "iteration,start_ns,t_phy_ns,t_net_ns,t_total_ns,t_overhead_ns,stf,lag_ns\n";
}

MetricsCsvWriter::MetricsCsvWriter(const std::string& path, int rows_per_flush)
    : file_(path, std::string(Header(), std::strlen(Header()) - 1), rows_per_flush,
            "metrics file") {}

void MetricsCsvWriter::Append(const IterationMetrics& r) {
  char line[256];
  const int n =
      std::snprintf(line, sizeof line, "%lld,%lld,%lld,%lld,%lld,%lld,%.6f,%lld",
                    static_cast<long long>(r.iteration), static_cast<long long>(r.start_ns),
                    static_cast<long long>(r.t_phy_ns), static_cast<long long>(r.t_net_ns),
                    static_cast<long long>(r.t_total_ns), static_cast<long long>(r.t_overhead_ns),
                    r.stf, static_cast<long long>(r.lag_ns));
  file_.Append(std::string_view(line, static_cast<size_t>(n)));
}

Distribution Distribute(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  const auto rank = [&](double p) {
    // Nearest rank: ceil(p/100 * n), 1-based.
    size_t r = static_cast<size_t>(std::ceil(p / 100.0 * static_cast<double>(values.size())));
    return values[std::clamp<size_t>(r, 1, values.size()) - 1];
  };
  d.mean = sum / static_cast<double>(values.size());
  d.p50 = rank(50);
  d.p99 = rank(99);
  d.max = values.back();
  return d;
}

MetricsSummary MetricsCollector::Summarize() const {
  MetricsSummary s;
  s.iterations = static_cast<int64_t>(rows_.size());
  std::vector<double> phy, net, total, overhead, stf, lag;
  double overhead_sum = 0, total_sum = 0;
  const auto ms = [](TimeNs ns) { return static_cast<double>(ns) / kNsPerMs; };
  for (const IterationMetrics& r : rows_) {
    phy.push_back(ms(r.t_phy_ns));
    net.push_back(ms(r.t_net_ns));
    total.push_back(ms(r.t_total_ns));
    overhead.push_back(ms(r.t_overhead_ns));
    stf.push_back(r.stf);
    lag.push_back(ms(r.lag_ns));
    overhead_sum += static_cast<double>(r.t_overhead_ns);
    total_sum += static_cast<double>(r.t_total_ns);
  }
  s.t_phy_ms = Distribute(phy);
  s.t_net_ms = Distribute(net);
  s.t_total_ms = Distribute(total);
  s.t_overhead_ms = Distribute(overhead);
  s.stf = Distribute(stf);
  s.lag_ms = Distribute(lag);
  s.overhead_share = total_sum > 0 ? overhead_sum / total_sum : 0;
  return s;
}

namespace {
std::string Line(const char* name, const Distribution& d, const char* unit) {
  char text[160];
  std::snprintf(text, sizeof text, "  %-11s mean %9.4f  p50 %9.4f  p99 %9.4f  max %9.4f %s\n", name,
                d.mean, d.p50, d.p99, d.max, unit);
  return text;
}
std::string Json(const char* name, const Distribution& d) {
  char text[200];
  std::snprintf(text, sizeof text, "\"%s\":{\"mean\":%.6g,\"p50\":%.6g,\"p99\":%.6g,\"max\":%.6g}",
                name, d.mean, d.p50, d.p99, d.max);
  return text;
}
}  // namespace

std::string MetricsSummary::ToText() const {
  std::string text = "coordinator: " + std::to_string(iterations) + " iterations\n";
  text += Line("T_phy", t_phy_ms, "ms");
  text += Line("T_net", t_net_ms, "ms");
  text += Line("T_total", t_total_ms, "ms");
  text += Line("T_overhead", t_overhead_ms, "ms");
  text += Line("STF", stf, "");
  text += Line("lag", lag_ms, "ms");
  char share[80];
  std::snprintf(share, sizeof share, "  overhead share %.2f %% of T_total\n", 100 * overhead_share);
  return text + share;
}

std::string MetricsSummary::ToJson() const {
  char share[64];
  std::snprintf(share, sizeof share, "\"overhead_share\":%.6g", overhead_share);
  return "{\"iterations\":" + std::to_string(iterations) + "," + Json("t_phy_ms", t_phy_ms) + "," +
         Json("t_net_ms", t_net_ms) + "," + Json("t_total_ms", t_total_ms) + "," +
         Json("t_overhead_ms", t_overhead_ms) + "," + Json("stf", stf) + "," +
         Json("lag_ms", lag_ms) + "," + share + "}";
}

}  // namespace sitlnet::coordinator
