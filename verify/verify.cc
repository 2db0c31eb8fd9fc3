// `sitlnet verify`: read the record, rerun (or take a second folder), compare, print.
#include <cstdio>
#include <ctime>

#include "verify/verify.h"

namespace sitlnet::verify {
namespace {

std::string DefaultRerunDir(std::string run_dir) {
  while (run_dir.size() > 1 && run_dir.back() == '/') run_dir.pop_back();
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::strftime(stamp, sizeof stamp, "%Y%m%d-%H%M%S", std::gmtime(&now));
  return run_dir + "-verify-" + stamp;
}

// One line per output on stdout, then the count of each verdict; sets the exit code.
void Report(const RunRecord& a, const RunRecord& b, OutputSet outputs, VerifyReport* report) {
  if (a.version != b.version) {
    std::fprintf(stderr,
                 "sitlnet verify: warning: %s was written by sitlnet %s, %s by %s: a difference "
                 "may come from the change between them\n",
                 a.run_dir.c_str(), a.version.c_str(), b.run_dir.c_str(), b.version.c_str());
  }
  if (a.scenario_text != b.scenario_text) {
    std::fprintf(stderr, "sitlnet verify: warning: %s and %s ran different scenarios\n",
                 a.run_dir.c_str(), b.run_dir.c_str());
  }
  report->outputs = CompareRunFolders(a, b, outputs);
  int counts[4] = {};
  for (const OutputVerdict& output : report->outputs) {
    ++counts[static_cast<int>(output.verdict)];
    std::printf("%s: %s%s%s\n", output.path.c_str(), VerdictName(output.verdict),
                output.detail.empty() ? "" : ": ", output.detail.c_str());
  }
  const int differ = counts[static_cast<int>(Verdict::kDiffers)];
  // Nothing same or within bound proves nothing: say so, and fail.
  const bool compared = counts[static_cast<int>(Verdict::kSame)] +
                            counts[static_cast<int>(Verdict::kWithinBound)] >
                        0;
  std::printf("%d same, %d within bound, %d not compared, %d differ: %s\n",
              counts[static_cast<int>(Verdict::kSame)],
              counts[static_cast<int>(Verdict::kWithinBound)],
              counts[static_cast<int>(Verdict::kNotCompared)], differ,
              differ > 0 ? "not reproduced" : compared ? "reproduced" : "nothing compared");
  std::fflush(stdout);
  report->exit_code = differ == 0 && compared ? 0 : 1;
}

}  // namespace

VerifyReport VerifyByRerun(const std::string& run_dir, const std::string& rerun_dir,
                           runner::RunOptions run_options) {
  const RunRecord original = ReadRunRecord(run_dir);
  RefuseUnreproducible(original);
  VerifyReport report;
  report.rerun_dir = rerun_dir.empty() ? DefaultRerunDir(run_dir) : rerun_dir;
  // The recorded scenario, named as the original named it (scenario.textproto's first line).
  run_options.scenario_path = original.source;
  run_options.scenario_text = original.scenario_text;
  run_options.out_dir = report.rerun_dir;
  run_options.one_host = true;  // A fleet's outputs equal the one-host run's (docs/scale-out.md).
  run_options.record_losses = original.outputs.count("losses.csv.gz") > 0;
  // A run without gcs.tlog had no GCS relay (`--gcs none`, or no ground station): nor has this.
  if (original.outputs.count("gcs.tlog") == 0) run_options.gcs = {"none"};
  std::fprintf(stderr, "sitlnet verify: rerunning %s (seed %llu, lockstep) into %s\n",
               run_dir.c_str(), static_cast<unsigned long long>(original.seed),
               report.rerun_dir.c_str());
  const runner::RunReport rerun = runner::RunScenario(run_options);
  if (rerun.interrupted) {
    report.exit_code = 130;
    return report;
  }
  Report(original, ReadRunRecord(report.rerun_dir), OutputSet::kReference, &report);
  return report;
}

VerifyReport VerifyTwoFolders(const std::string& run_dir_a, const std::string& run_dir_b) {
  const RunRecord a = ReadRunRecord(run_dir_a);
  const RunRecord b = ReadRunRecord(run_dir_b);
  RefuseUnreproducible(a);
  RefuseUnreproducible(b);
  VerifyReport report;
  Report(a, b, OutputSet::kEither, &report);
  return report;
}

}  // namespace sitlnet::verify
