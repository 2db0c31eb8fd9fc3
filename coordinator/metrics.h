// Per-iteration timing metrics (DANCERS paper, Sec. V: STF, T_overhead),
// metrics.csv and the end-of-run summary.
#ifndef SITLNET_COORDINATOR_METRICS_H_
#define SITLNET_COORDINATOR_METRICS_H_

#include <cstdint>
#include <string>
#include <vector>

#include "common/common.h"

namespace sitlnet::coordinator {

// One iteration, all durations wall-clock nanoseconds.
struct IterationMetrics {
  int64_t iteration = 0;
  TimeNs start_ns = 0;       // Virtual start of the iteration.
  TimeNs t_phy_ns = 0;       // Physics connector's busy time (its End.busy_ns).
  TimeNs t_net_ns = 0;       // Network connector's busy time.
  TimeNs t_total_ns = 0;     // First START sent -> last END decoded, at the coordinator.
  TimeNs t_overhead_ns = 0;  // t_total - max(t_phy, t_net); may be slightly < 0 (clock reads).
  double stf = 0;            // t_total / Δ.
  TimeNs lag_ns = 0;         // Realtime: how late the iteration ended; lockstep: 0.
};

// Fills t_overhead_ns and stf from the other fields (Eq. 3 and the overhead
// definition of the DANCERS paper).
void CompleteMetrics(TimeNs iteration_ns, IterationMetrics* metrics);

// Writes metrics.csv. Rows are buffered and written only as whole lines, one
// write(2) per flush, so an interrupted run leaves a file of complete rows.
class MetricsCsvWriter {
 public:
  // Creates/truncates `path` and writes the header. Throws Error naming the path.
  explicit MetricsCsvWriter(const std::string& path, int rows_per_flush = 100);
  MetricsCsvWriter(const MetricsCsvWriter&) = delete;
  MetricsCsvWriter& operator=(const MetricsCsvWriter&) = delete;

  void Append(const IterationMetrics& row);
  void Flush() { file_.Flush(); }
  static const char* Header();

 private:
  LineFile file_;  // Flushes at destruction.
};

// mean / p50 / p99 of one column.
struct Distribution {
  double mean = 0;
  double p50 = 0;
  double p99 = 0;
  double max = 0;
};
// Nearest-rank percentiles (the smallest value with at least p % of the
// samples at or below it). Empty input: all zero.
Distribution Distribute(std::vector<double> values);

struct MetricsSummary {
  int64_t iterations = 0;
  Distribution t_phy_ms, t_net_ms, t_total_ms, t_overhead_ms, stf, lag_ms;
  // sum(T_overhead) / sum(T_total): the paper's overhead share over the run.
  double overhead_share = 0;
  std::string ToText() const;  // A few human-readable lines.
  std::string ToJson() const;  // One JSON object (for summary.json).
};

// Accumulates rows for the summary (keeps every row: 8 numbers per
// iteration, 6 MB per simulated hour at Δ = 10 ms).
class MetricsCollector {
 public:
  void Add(const IterationMetrics& row) { rows_.push_back(row); }
  MetricsSummary Summarize() const;
  const std::vector<IterationMetrics>& rows() const { return rows_; }

 private:
  std::vector<IterationMetrics> rows_;
};

}  // namespace sitlnet::coordinator

#endif  // SITLNET_COORDINATOR_METRICS_H_
