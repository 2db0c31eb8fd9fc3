#include "coordinator/metrics.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <fstream>
#include <sstream>

namespace sitlnet::coordinator {
namespace {

TEST(Metrics, OverheadAndStfFollowTheDancersDefinitions) {
  IterationMetrics m;
  m.t_phy_ns = 3 * kNsPerMs;
  m.t_net_ns = 7 * kNsPerMs;
  m.t_total_ns = 8 * kNsPerMs;
  CompleteMetrics(10 * kNsPerMs, &m);
  EXPECT_EQ(m.t_overhead_ns, 1 * kNsPerMs);  // 8 - max(3, 7)
  EXPECT_DOUBLE_EQ(m.stf, 0.8);              // 8 / 10
}

TEST(Metrics, NearestRankPercentiles) {
  std::vector<double> values;
  for (int i = 100; i >= 1; --i) values.push_back(i);  // Unsorted on purpose.
  const Distribution d = Distribute(values);
  EXPECT_DOUBLE_EQ(d.mean, 50.5);
  EXPECT_DOUBLE_EQ(d.p50, 50);
  EXPECT_DOUBLE_EQ(d.p99, 99);
  EXPECT_DOUBLE_EQ(d.max, 100);
  const Distribution one = Distribute({4.0});
  EXPECT_DOUBLE_EQ(one.p50, 4);
  EXPECT_DOUBLE_EQ(one.p99, 4);
  const Distribution three = Distribute({1, 2, 30});  // ceil(0.5*3)=2, ceil(0.99*3)=3
  EXPECT_DOUBLE_EQ(three.p50, 2);
  EXPECT_DOUBLE_EQ(three.p99, 30);
  EXPECT_DOUBLE_EQ(Distribute({}).p99, 0);
}

TEST(Metrics, OverheadShareIsRatioOfSums) {
  MetricsCollector collector;
  IterationMetrics a;
  a.t_total_ns = 10;
  a.t_overhead_ns = 1;
  IterationMetrics b;
  b.t_total_ns = 30;
  b.t_overhead_ns = 1;
  collector.Add(a);
  collector.Add(b);
  EXPECT_DOUBLE_EQ(collector.Summarize().overhead_share, 2.0 / 40.0);
}

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

TEST(MetricsCsvWriter, WritesOnlyWholeRows) {
  const std::string path = "/tmp/sitlnet-metrics-test-" + std::to_string(getpid()) + ".csv";
  {
    MetricsCsvWriter writer(path, /*rows_per_flush=*/2);
    EXPECT_EQ(ReadFile(path), MetricsCsvWriter::Header());  // Header at once.
    IterationMetrics m;
    m.iteration = 0;
    m.start_ns = 0;
    m.t_phy_ns = 1;
    m.t_net_ns = 2;
    m.t_total_ns = 3;
    CompleteMetrics(10, &m);
    writer.Append(m);
    EXPECT_EQ(ReadFile(path), MetricsCsvWriter::Header());  // Buffered, not half-written.
    m.iteration = 1;
    m.start_ns = 10;
    writer.Append(m);
    EXPECT_EQ(ReadFile(path), std::string(MetricsCsvWriter::Header()) +
                                  "0,0,1,2,3,1,0.300000,0\n1,10,1,2,3,1,0.300000,0\n");
    m.iteration = 2;
    writer.Append(m);
  }  // Destructor flushes the third row.
  const std::string text = ReadFile(path);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 4);
  EXPECT_EQ(text.back(), '\n');
  unlink(path.c_str());
}

TEST(MetricsCsvWriter, NamesTheFileItCannotCreate) {
  try {
    MetricsCsvWriter writer("/nonexistent-dir/metrics.csv");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "create metrics file \"/nonexistent-dir/metrics.csv\": No such file or directory");
  }
}

}  // namespace
}  // namespace sitlnet::coordinator
