// RunSweep with a stand-in for `sitlnet run` (a shell script that writes a summary.json whose
// stf mean is its seed): resume, failures, the job slots in use at once, and the two tables.
#include <gtest/gtest.h>
#include <cerrno>
#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <set>
#include <sstream>

#include "common/common.h"
#include "sweep/sweep.h"

namespace sitlnet::sweep {
namespace {

std::string ReadAll(const std::string& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

int CountLines(const std::string& path) {
  std::ifstream file(path);
  std::string line;
  int lines = 0;
  while (std::getline(file, line)) ++lines;
  return lines;
}

class SweepResumeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char pattern[] = "/tmp/sweep_resume_XXXXXX";
    dir_ = mkdtemp(pattern);
    scenario_ = dir_ + "/s.textproto";
    std::ofstream(scenario_) << "name: \"s\"\nrobot { name: \"a\" }\nrobot { name: \"b\" }\n";
    // Arguments: run INPUT --out FOLDER --seed S --no-progress. Seed 3 fails while the file
    // `fail` exists. Each call appends "<scenario name>" to calls.log; the name's job slot is
    // checked free (a lock folder per name) while it runs.
    fake_ = dir_ + "/fake_sitlnet";
    std::ofstream(fake_) << "#!/bin/sh\n"
                         << "echo $$ >> " << dir_ << "/pids.log\n"
                         << "name=$(sed -n 's/^name: \"\\(.*\\)\"/\\1/p' \"$2\")\n"
                         << "trap 'echo end >> " << dir_ << "/ended.log; exit 130' INT\n"
                         << "echo \"$name\" >> " << dir_ << "/calls.log\n"
                         << "mkdir " << dir_ << "/lock-$name || { echo clash >> " << dir_
                         << "/clash.log; }\n"
                         << "sleep 0.05\n"
                         << "rmdir " << dir_ << "/lock-$name\n"
                         << "if [ \"$6\" = 3 ] && [ -e " << dir_ << "/fail ]; then\n"
                         << "  echo 'sitlnet run: first line' >&2\n"
                         << "  echo 'sitlnet run: the reason' >&2; exit 2; fi\n"
                         << "echo '{\"interrupted\":false,\"failure\":null,\"metrics\":"
                            "{\"stf\":{\"mean\":'\"$6\"'}}}' > \"$4/summary.json\"\n"
                         << "echo end >> " << dir_ << "/ended.log\n";
    chmod(fake_.c_str(), 0755);
  }

  SweepOptions Options() const {
    SweepOptions options;
    options.scenario_path = scenario_;
    options.axes = {{"radio.rate_mbps", {"6", "54"}}};
    options.seeds = {1, 2, 3};
    options.metrics = {"metrics.stf.mean"};
    options.jobs = 2;
    options.out_dir = dir_ + "/out";
    options.sitlnet_exe = fake_;
    return options;
  }

  std::string dir_, scenario_, fake_;
};

TEST_F(SweepResumeTest, RecordsAFailureResumesWithoutRerunningAndTabulates) {
  std::ofstream(dir_ + "/fail") << "";
  const SweepReport first = RunSweep(Options());
  EXPECT_EQ(first.points, 6);
  EXPECT_EQ(first.ran, 6);
  EXPECT_EQ(first.failed, 2);
  EXPECT_EQ(first.exit_code, 1);
  EXPECT_EQ(CountLines(dir_ + "/calls.log"), 6);
  EXPECT_EQ(CountLines(dir_ + "/clash.log"), 0);
  // Two slots, two names: never the same name twice at once, never a third.
  std::set<std::string> names;
  std::ifstream calls(dir_ + "/calls.log");
  for (std::string name; std::getline(calls, name);) names.insert(name);
  EXPECT_EQ(names.size(), 2u);
  EXPECT_EQ(ReadAll(dir_ + "/out/radio.rate_mbps=6,seed=3/sweep-failure.txt"),
            "exit 2: sitlnet run: the reason\n");

  const std::string points = ReadAll(dir_ + "/out/points.csv");
  EXPECT_NE(points.find("point,radio.rate_mbps,seed,status,reason,metrics.stf.mean\n"),
            std::string::npos);
  EXPECT_NE(points.find("\"radio.rate_mbps=6,seed=1\",6,1,ok,,1\n"), std::string::npos) << points;
  EXPECT_NE(points.find("\"radio.rate_mbps=54,seed=3\",54,3,failed,exit 2: sitlnet run: the "
                        "reason,\n"),
            std::string::npos)
      << points;
  // Seeds 1 and 2 finished per rate: mean 1.5, sd sqrt(0.5), t(0.975, 1) = 12.706 (table).
  const std::string summary = ReadAll(dir_ + "/out/summary.csv");
  EXPECT_NE(summary.find("radio.rate_mbps,metric,n,mean,sd,ci95_half_width\n"), std::string::npos);
  EXPECT_NE(summary.find("6,metrics.stf.mean,2,1.5,0.7071067812,6.35"), std::string::npos)
      << summary;

  // The failed points run again; the finished ones do not.
  std::remove((dir_ + "/fail").c_str());
  const SweepReport second = RunSweep(Options());
  EXPECT_EQ(second.already_finished, 4);
  EXPECT_EQ(second.ran, 2);
  EXPECT_EQ(second.failed, 0);
  EXPECT_EQ(second.exit_code, 0);
  EXPECT_EQ(CountLines(dir_ + "/calls.log"), 8);
  EXPECT_FALSE(std::ifstream(dir_ + "/out/radio.rate_mbps=6,seed=3/sweep-failure.txt"));

  const SweepReport third = RunSweep(Options());
  EXPECT_EQ(third.already_finished, 6);
  EXPECT_EQ(third.ran, 0);
  EXPECT_EQ(CountLines(dir_ + "/calls.log"), 8);
}

// A point that cannot be prepared (its folder is a file) ends the sweep with that error, after
// the runs already started ended: none is left behind unwaited.
TEST_F(SweepResumeTest, StopsOnAPointItCannotPrepare) {
  SweepOptions options = Options();
  mkdir(options.out_dir.c_str(), 0755);
  std::ofstream(options.out_dir + "/radio.rate_mbps=54,seed=1") << "";
  try {
    RunSweep(options);
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("radio.rate_mbps=54,seed=1/point.textproto"),
              std::string::npos)
        << error.what();
  }
  // Points 1-3 started before it (how far each got before the stop depends on the host's
  // scheduling); every one had ended, stopped or finished, when RunSweep returned: no process
  // it started is left.
  std::ifstream pids(dir_ + "/pids.log");
  int started = 0;
  for (pid_t pid; pids >> pid; ++started) {
    EXPECT_TRUE(kill(pid, 0) == -1 && errno == ESRCH) << "run " << pid << " outlived the sweep";
  }
  EXPECT_GE(started, 1);
  EXPECT_LE(started, 3);
}

// A cluster's sweep (issue 48, item 3): each point run alone by its index, as an Indexed Job's
// pods run them, into one folder; --collect then tabulates. Oracle: the tables one ordinary sweep
// of the same grid writes (points.csv and summary.csv byte for byte: the stand-in's metric is
// its seed). Before every point has run, --collect names the missing ones and fails.
TEST_F(SweepResumeTest, PointsRunOneByOneThenCollectedGiveTheSweepsTables) {
  SweepOptions whole = Options();
  whole.out_dir = dir_ + "/whole";
  ASSERT_EQ(RunSweep(whole).exit_code, 0);

  SweepOptions collect = Options();
  collect.collect_only = true;
  const SweepReport empty = RunSweep(collect);
  EXPECT_EQ(empty.not_run, 6);
  EXPECT_EQ(empty.ran, 0);
  EXPECT_EQ(empty.exit_code, 1);
  for (size_t index = 0; index < 6; ++index) {
    SweepOptions pod = Options();
    pod.only_point = index;
    const SweepReport report = RunSweep(pod);
    EXPECT_EQ(report.ran, 1) << index;
    EXPECT_EQ(report.exit_code, 0) << index;
    if (index == 2) {  // Half the pods have ended.
      const SweepReport half = RunSweep(collect);
      EXPECT_EQ(half.already_finished, 3);
      EXPECT_EQ(half.not_run, 3);
      EXPECT_EQ(half.exit_code, 1);
    }
  }
  EXPECT_EQ(CountLines(dir_ + "/calls.log"), 12);  // 6 whole, then 6 pods; collect runs none
  const SweepReport all = RunSweep(collect);
  EXPECT_EQ(all.already_finished, 6);
  EXPECT_EQ(all.exit_code, 0);
  EXPECT_EQ(CountLines(dir_ + "/calls.log"), 12);
  for (const char* table : {"/points.csv", "/summary.csv"}) {
    EXPECT_EQ(ReadAll(collect.out_dir + table), ReadAll(whole.out_dir + table)) << table;
  }

  // A point whose run fails: recorded, and the pod ends with 0 (a Job would only rerun it);
  // --collect reports it and fails.
  std::ofstream(dir_ + "/fail") << "";
  SweepOptions failing = Options();
  failing.out_dir = dir_ + "/failing";
  failing.only_point = 2;  // rate 6, seed 3
  const SweepReport failed = RunSweep(failing);
  EXPECT_EQ(failed.failed, 1);
  EXPECT_EQ(failed.exit_code, 0);
  EXPECT_TRUE(std::ifstream(failing.out_dir + "/radio.rate_mbps=6,seed=3/sweep-failure.txt"));
  failing.only_point.reset();
  failing.collect_only = true;
  const SweepReport collected = RunSweep(failing);
  EXPECT_EQ(collected.failed, 1);
  EXPECT_EQ(collected.not_run, 5);
  EXPECT_EQ(collected.exit_code, 1);
  std::remove((dir_ + "/fail").c_str());

  SweepOptions past = Options();
  past.only_point = 6;
  try {
    RunSweep(past);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "--point 6: the sweep has 6 points (0 to 5)");
  }
}

// Plots (issue 48, item 2): the stand-in's metric is its seed, so each rate's mean over seeds
// 1-3 is 2 and its 95 % interval half-width is t(0.975, 2) / sqrt(3) = 4.302653 / 1.732051 =
// 2.48413 (the published t table). gnuplot draws one PNG per metric and swept field.
TEST_F(SweepResumeTest, PlotsTheMeanWithItsIntervalAgainstEachSweptField) {
  SweepOptions options = Options();
  options.axes.push_back({"timing.duration_ms", {"1000"}});  // One value: no plot against it.
  ASSERT_EQ(RunSweep(options).exit_code, 0);
  const std::string script = ReadAll(options.out_dir + "/plots.gnuplot");
  EXPECT_NE(script.find("6 2 2.48413"), std::string::npos) << script;
  EXPECT_NE(script.find("54 2 2.48413"), std::string::npos) << script;
  EXPECT_NE(script.find("set output 'plot_metrics_stf_mean_vs_radio_rate_mbps.png'"),
            std::string::npos)
      << script;
  EXPECT_EQ(script.find("vs_timing_duration_ms"), std::string::npos) << script;
  if (RunProgramQuietly({"gnuplot", "--version"}) != 0) {
    if (std::getenv("CI") == nullptr || std::string(std::getenv("CI")) != "true") {
      GTEST_SKIP() << "no gnuplot (apt-get install gnuplot-nox; scripts/setup does)";
    }
    FAIL() << "no gnuplot (CI=true: scripts/setup installs it)";
  }
  const std::string png = ReadAll(options.out_dir + "/plot_metrics_stf_mean_vs_radio_rate_mbps.png");
  ASSERT_GT(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  EXPECT_EQ(ReadAll(options.out_dir + "/plots.log"), "");  // gnuplot said nothing
}

TEST_F(SweepResumeTest, RefusesABadValueBeforeAnyRun) {
  SweepOptions options = Options();
  options.axes = {{"radio.rate_mbps", {"6", "7"}}};
  try {
    RunSweep(options);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()).rfind("--set radio.rate_mbps=7: ", 0), 0u) << error.what();
  }
  options.axes = {{"radio.rate", {"6"}}};
  try {
    RunSweep(options);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()), "--set radio.rate=6: Radio has no field \"rate\"");
  }
  options.axes = {{"timing.seed", {"6"}}};
  EXPECT_THROW(RunSweep(options), Error);
  EXPECT_FALSE(std::ifstream(dir_ + "/calls.log"));
}

// --set robot_count (issue 48, item 5): each point's scenario holds the first N robots of the
// file's two; it applies before the other fields whatever the flags' order, so a field of a
// robot the point lacks is refused by name; a count past the file's robots names the flag.
TEST_F(SweepResumeTest, RobotCountKeepsTheFirstRobotsOfEachPoint) {
  SweepOptions options = Options();
  options.axes = {{"robot[0].position_m.x", {"3"}}, {"robot_count", {"1", "2"}}};
  options.seeds = {1};
  ASSERT_EQ(RunSweep(options).exit_code, 0);
  const std::string prefix = options.out_dir + "/robot[0].position_m.x=3,robot_count=";
  const std::string one = ReadAll(prefix + "1,seed=1/point.textproto");
  const std::string two = ReadAll(prefix + "2,seed=1/point.textproto");
  EXPECT_NE(one.find("name: \"a\""), std::string::npos) << one;
  EXPECT_EQ(one.find("name: \"b\""), std::string::npos) << one;
  EXPECT_NE(two.find("name: \"b\""), std::string::npos) << two;
  EXPECT_NE(one.find("x: 3"), std::string::npos) << one;

  options.axes = {{"robot[1].position_m.x", {"3"}}, {"robot_count", {"2", "1"}}};
  try {
    RunSweep(options);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "--set robot[1].position_m.x=3: index 1 past the scenario's 1 robot");
  }
  options.axes = {{"robot_count", {"1", "3"}}};
  try {
    RunSweep(options);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              "--set robot_count=3: \"3\" is not a robot count from 1 to the 2 robots the "
              "scenario lists (robot_count keeps the first N)");
  }
}

}  // namespace
}  // namespace sitlnet::sweep
