// Reading summary.json: what makes a point finished, and numbers by path.
#include <gtest/gtest.h>

#include <fstream>

#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

// The shape runner/summary.cc writes, cut down.
constexpr char kFinished[] =
    R"({"scenario":"x","seed":3,"interrupted":false,"failure":null,)"
    R"("metrics":{"iterations":100,"stf":{"mean":0.25,"p50":0.2}},)"
    R"("connectivity":{"first_split_s":null,"max_components":2},)"
    R"("robots":[{"name":"a","medium":{"sent":7}},{"name":"b","medium":{"sent":9}}],"ok":true})";

std::string WriteTemp(const std::string& name, const std::string& text) {
  const std::string path = ::testing::TempDir() + "/sweep_summary_" + name + ".json";
  std::ofstream(path, std::ios::trunc) << text;
  return path;
}

TEST(SummaryJsonTest, ReadsNumbersByPath) {
  const auto summary = ReadSummaryJson(WriteTemp("finished", kFinished));
  ASSERT_TRUE(summary);
  EXPECT_TRUE(IsFinishedSummary(*summary));
  EXPECT_EQ(SummaryMetric(*summary, "metrics.stf.mean"), 0.25);
  EXPECT_EQ(SummaryMetric(*summary, "metrics.iterations"), 100);
  EXPECT_EQ(SummaryMetric(*summary, "robots[1].medium.sent"), 9);
  EXPECT_EQ(SummaryMetric(*summary, "ok"), 1);
  EXPECT_FALSE(SummaryMetric(*summary, "connectivity.first_split_s"));  // null
  EXPECT_FALSE(SummaryMetric(*summary, "scenario"));                    // text
  EXPECT_FALSE(SummaryMetric(*summary, "metrics.stf"));                 // an object
  EXPECT_FALSE(SummaryMetric(*summary, "robots[2].medium.sent"));       // past the list
  EXPECT_FALSE(SummaryMetric(*summary, "metrics.nothing.mean"));
}

TEST(SummaryJsonTest, OnlyAWholeUninterruptedFaultlessSummaryIsFinished) {
  const std::string text = kFinished;
  EXPECT_FALSE(ReadSummaryJson(WriteTemp("cut", text.substr(0, text.size() / 2))));
  EXPECT_FALSE(ReadSummaryJson(::testing::TempDir() + "/sweep_no_such.json"));
  std::string interrupted = text;
  interrupted.replace(interrupted.find("\"interrupted\":false"), 19, "\"interrupted\":true");
  EXPECT_FALSE(IsFinishedSummary(*ReadSummaryJson(WriteTemp("interrupted", interrupted))));
  std::string failed = text;
  failed.replace(failed.find("\"failure\":null"), 14, "\"failure\":\"robot a exited 1\"");
  EXPECT_FALSE(IsFinishedSummary(*ReadSummaryJson(WriteTemp("failed", failed))));
  EXPECT_FALSE(IsFinishedSummary(*ReadSummaryJson(WriteTemp("bare", "{}"))));
}

}  // namespace
}  // namespace sitlnet::sweep
