// The stages of `sitlnet run` (runner/run.cc) one by one, with real namespaces, MuJoCo, the
// medium and robot images: the setup brings every part up and takes it down, also when it fails
// half-way; the run steps every iteration with the robots supervised; the report turns the
// outcome into the exit code and summary.json.
#include <signal.h>

#include <algorithm>
#include <string>

#include "runner/coordinated_run.h"
#include "runner/local_physics.h"
#include "runner/robot_stop.h"
#include "runner/run_folder.h"
#include "runner/run_report.h"
#include "runner/run_setup.h"
#include "runner/runner.h"
#include "tests/integration/nns_test_util.h"
#include "tests/integration/run_test_util.h"

namespace sitlnet::nns::testing {
namespace {

// The options `sitlnet run SCENARIO --no-progress --rt-priority 0` would give, with the pacing
// asked for: no SCHED_FIFO for the test process.
runner::RunOptions OptionsFor(const RunScenario& scenario, bool lockstep) {
  runner::RunOptions options;
  options.scenario_path = scenario.path;
  options.sitlnet_exe = SitlnetBinary();
  options.images_root = integration_test::SourceDir() + "/robot_images";
  options.progress = false;
  options.realtime_priority = 0;
  options.pacing = lockstep ? clock::Pacing::kLockstep : clock::Pacing::kRealtime;
  return options;
}

Scenario Load(const runner::RunOptions& options) {
  return runner::ApplyRunOverrides(LoadScenarioFile(options.scenario_path), options);
}

std::string RunFolder(const RunScenario& scenario) {
  const std::string dir = TempDir() + "/" + scenario.name + "-out";
  runner::MakeRunFolder(dir);
  return dir;
}

// A scenario written for one test, its options and loaded form, its run folder; taken down at the
// test's end whatever happens.
struct StagedScenario {
  StagedScenario(int slot, const std::string& robots, const std::string& extra, bool lockstep)
      : scenario(WriteScenario(slot, robots, extra)),
        guard(scenario.name),
        options(OptionsFor(scenario, lockstep)),
        loaded(Load(options)),
        dir(RunFolder(scenario)) {}
  RunScenario scenario;
  DownGuard guard;
  runner::RunOptions options;
  Scenario loaded;
  std::string dir;
};

int64_t Lines(const std::string& text) { return std::count(text.begin(), text.end(), '\n'); }

// Runs the stages after the setup, as RunScenario does, and returns the report.
runner::RunReport RunAndReport(runner::RunSetup* setup, const runner::RunOptions& options,
                               const std::string& dir, runner::LoopOutcome* loop) {
  runner::RunReport report;
  report.run_dir = dir;
  runner::LocalPhysics physics(setup, options, dir);
  runner::CoordinatedRun run(setup, &physics, options, dir, -1);
  *loop = run.Run();
  runner::StopRobots(&setup->robots(), &setup->clock_publishers(), &report);
  setup->medium_records().Flush();
  runner::ReportRun(*setup, *loop, &report);
  return report;
}

TEST(RunStagesTest, SetupBringsEveryPartUpAndTakesItDownInReverse) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const StagedScenario staged(
      4, "robot { name: \"a\" image: \"shell\" args: \"sleep 60\" }\nrobot { name: \"b\" }\n", "",
      false);
  pid_t image_pid = 0;
  {
    runner::RunSetup setup(staged.loaded, staged.options, staged.dir, nullptr);
    EXPECT_TRUE(NetnsExists(staged.scenario.name + "-a"));
    EXPECT_TRUE(NetnsExists(staged.scenario.name + "-b"));
    EXPECT_TRUE(NetnsExists(CtlNetnsName(staged.scenario.name)));
    ASSERT_EQ(setup.robots().size(), 2u);
    ASSERT_NE(setup.robots()[0].process, nullptr);
    EXPECT_EQ(setup.robots()[1].process, nullptr);  // No image.
    image_pid = setup.robots()[0].process->pid();
    EXPECT_EQ(kill(image_pid, 0), 0);
    EXPECT_EQ(setup.bridge().robot_count(), 2);
    EXPECT_EQ(setup.remote_medium(), nullptr);
    EXPECT_EQ(setup.shared_time(), nullptr);  // No timing.ros2_clock_hz.
    setup.medium_records().Flush();
    // Nothing crossed the air yet: the pcap's file header (24 bytes) and the CSV header alone.
    EXPECT_EQ(ReadAll(staged.dir + "/medium.pcap").size(), 24u);
    EXPECT_EQ(ReadAll(staged.dir + "/deliveries.csv"), "time_ns,from,to,rx_power_dbm,sinr_db\n");
  }
  EXPECT_NE(kill(image_pid, 0), 0);  // Stopped and reaped.
  ExpectNothingLeft(staged.scenario.name);
}

TEST(RunStagesTest, ASetupThatFailsHalfWayLeavesNothing) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const StagedScenario staged(
      5, "robot { name: \"a\" image: \"shell\" args: \"exit 3\" }\nrobot { name: \"b\" }\n", "",
      false);
  try {
    runner::RunSetup setup(staged.loaded, staged.options, staged.dir, nullptr);
    FAIL() << "no Error";
  } catch (const Error& error) {
    EXPECT_EQ(
        std::string(error.what()),
        "robot \"a\": its image exited at once with status 3; see " + staged.dir + "/robots/a.log");
  }
  ExpectNothingLeft(staged.scenario.name);
}

TEST(RunStagesTest, TheRunStepsEveryIterationAndTheReportSaysItEnded) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const StagedScenario staged(6, "robot { name: \"a\" }\nrobot { name: \"b\" }\n",
                              "timing { duration_ms: 1000 iteration_us: 10000 }\n", true);
  {
    runner::RunSetup setup(staged.loaded, staged.options, staged.dir, nullptr);
    runner::LoopOutcome loop;
    const runner::RunReport report = RunAndReport(&setup, staged.options, staged.dir, &loop);
    EXPECT_EQ(loop.failure, "");
    EXPECT_EQ(loop.result.iterations_done, 100);  // 1 s of 10 ms iterations.
    EXPECT_EQ(loop.metrics.iterations, 100);
    EXPECT_LE(loop.begin_ns, loop.end_ns);
    EXPECT_EQ(report.exit_code, 0);
    EXPECT_FALSE(report.interrupted);
  }
  // metrics.csv: a header and one row per iteration; trajectories.csv: a header and both robots
  // at t = 0 and every 100 ms (options.trajectory_period_ns) up to 1 s.
  EXPECT_EQ(Lines(ReadAll(staged.dir + "/metrics.csv")), 1 + 100);
  EXPECT_EQ(Lines(ReadAll(staged.dir + "/trajectories.csv")), 1 + 2 * 11);
  EXPECT_NE(ReadAll(staged.dir + "/summary.json").find("\"iterations\""), std::string::npos);
  ExpectNothingLeft(staged.scenario.name);
}

TEST(RunStagesTest, TheSupervisorStopsTheRunAtARobotFailureAndTheReportSaysSo) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const StagedScenario staged(
      7,
      "robot { name: \"a\" image: \"shell\" args: \"sleep 0.5; exit 3\" }\nrobot { name: \"b\" }\n",
      "timing { duration_ms: 20000 }\non_robot_failure: ROBOT_FAILURE_STOP\n", false);
  {
    runner::RunSetup setup(staged.loaded, staged.options, staged.dir, nullptr);
    runner::LoopOutcome loop;
    const runner::RunReport report = RunAndReport(&setup, staged.options, staged.dir, &loop);
    EXPECT_NE(loop.failure.find("robot \"a\" failed with status 3 (on_robot_failure: "
                                "ROBOT_FAILURE_STOP; log: " +
                                staged.dir + "/robots/a.log)"),
              std::string::npos)
        << loop.failure;
    EXPECT_LT(loop.metrics.iterations, 2000);  // Stopped before the scenario's end.
    EXPECT_EQ(setup.robots()[0].exit_status, 3);
    EXPECT_EQ(report.exit_code, 1);
  }
  EXPECT_NE(ReadAll(staged.dir + "/summary.json").find("\"name\":\"a\",\"exit_status\":3"),
            std::string::npos);
  ExpectNothingLeft(staged.scenario.name);
}

}  // namespace
}  // namespace sitlnet::nns::testing
