#include "runner/run_report.h"

#include <algorithm>
#include <cstdio>

#include "runner/summary.h"

namespace sitlnet::runner {
namespace {

// --remote network: the medium link's round trips on stderr and in the report.
void ReportMediumLink(const network_side::RemoteMedium& remote_medium, RunReport* report) {
  const network_side::MediumLinkStats& link = remote_medium.stats();
  report->medium_link = link;
  const network_side::MediumLinkStats::Means mean = link.PerRoundTrip();
  std::fprintf(stderr,
               "sitlnet run: medium link to %s: %lld round trips (%lld quiet steps without), "
               "mean %.1f us each (remote medium %.1f us, transport %.1f us), %.0f B out, "
               "%.0f B back\n",
               remote_medium.Describe().c_str(), static_cast<long long>(link.round_trips),
               static_cast<long long>(link.quiet_steps), mean.round_trip_us, mean.remote_medium_us,
               mean.transport_us, mean.request_bytes, mean.reply_bytes);
}

// A fleet's central: each node link's round trips and bytes on stderr.
void ReportFleetLinks(const std::vector<fleet::FleetLinkStats>& links) {
  for (const fleet::FleetLinkStats& node : links) {
    const coordinator::LinkStats& link = node.link;
    const auto us = [](TimeNs ns) { return static_cast<double>(ns) / kNsPerUs; };
    std::fprintf(stderr,
                 "sitlnet run: link to %s: %lld round trips (Start sent to End read: p50 %.1f us, "
                 "p99 %.1f us, max %.1f us), %.0f B up and %.0f B down per iteration (%lld B and "
                 "%lld B in all)\n",
                 node.description.c_str(), static_cast<long long>(link.round_trips),
                 us(link.round_trip_p50_ns), us(link.round_trip_p99_ns), us(link.round_trip_max_ns),
                 link.BytesUpPerRoundTrip(), link.BytesDownPerRoundTrip(),
                 static_cast<long long>(link.bytes_up), static_cast<long long>(link.bytes_down));
  }
}

// A fleet's central in realtime: each node's late entries and writes on stderr.
void ReportFleetRealtime(const std::vector<RunReport::NodeLateness>& nodes) {
  for (const RunReport::NodeLateness& node : nodes) {
    const auto ms = [](TimeNs ns) { return static_cast<double>(ns) / kNsPerMs; };
    const tapbridge::LatenessStats& entries = node.late_entries;
    const tapbridge::LatenessStats& writes = node.late_writes;
    std::fprintf(stderr,
                 "sitlnet run: %s: realtime: %llu frames entered the medium late by p50 %.3f, p99 "
                 "%.3f, max %.3f ms; %llu deliveries written late by p50 %.3f, p99 %.3f, max "
                 "%.3f ms\n",
                 node.description.c_str(), static_cast<unsigned long long>(entries.count),
                 ms(entries.p50_ns), ms(entries.p99_ns), ms(entries.max_ns),
                 static_cast<unsigned long long>(writes.count), ms(writes.p50_ns),
                 ms(writes.p99_ns), ms(writes.max_ns));
  }
}

}  // namespace

void ReportRun(RunParts& setup, const LoopOutcome& loop, RunReport* report) {
  const std::string& failure = loop.failure;
  report->interrupted = loop.result.interrupted;
  report->exit_code = !failure.empty() ? 1 : loop.result.interrupted ? 130 : 0;
  if (!failure.empty()) std::fprintf(stderr, "sitlnet run: %s\n", failure.c_str());
  network_side::RemoteMedium* remote_medium = setup.remote_medium();
  if (remote_medium) ReportMediumLink(*remote_medium, report);
  ReportFleetRealtime(report->fleet_realtime);
  ReportFleetLinks(report->fleet_links);
  // A failed run throws out of RunCoordinator before it returns a count: the
  // metrics have one row per iteration done.
  WriteSummaryAndPlots(setup.scenario(), *report, loop.metrics,
                       std::max<int64_t>(loop.result.iterations_done, loop.metrics.iterations),
                       setup.robots(), setup.bridge(), setup.local_physics(),
                       setup.medium_records(), loop.closest_approach, failure);
  if (remote_medium) {
    remote_medium->Stop(failure.empty() ? (loop.result.interrupted ? "interrupted" : "run finished")
                                        : failure);
  }
}

}  // namespace sitlnet::runner
