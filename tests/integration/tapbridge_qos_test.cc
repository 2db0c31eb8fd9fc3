// EDCA with real programs (issue 44, item 7): on 802.11n, robot b floods the link toward robot a
// with best-effort iperf3 while a pings b at voice (`ping -Q 0xc0`) and at best effort. Both
// bounds come from the standard's timing and the queue's length, computed here.
#include <gtest/gtest.h>
#include <poll.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <regex>
#include <string>
#include <vector>

#include "tests/integration/realtime_judge.h"
#include "tests/integration/tapbridge_test_util.h"

namespace sitlnet::tapbridge::testing {
namespace {

// 802.11n at 5 GHz, HT MCS 7 (65 Mb/s), 20 MHz, 800 ns guard interval, no aggregation: the
// scenario defaults of an 802.11n radio. 10 m apart: about 33 dB of SNR, far above MCS 7's need.
constexpr char kTwoHtRobots[] =
    "robot { name: \"a\" position_m { x: 0 y: 0 z: 1 } }\n"
    "robot { name: \"b\" position_m { x: 10 y: 0 z: 1 } }\n"
    "radio { standard: STANDARD_80211N_5GHZ mcs: 7 channel_width_mhz: 20 }\n";
constexpr int kQueueLimitFrames = 500;  // radio.queue_limit_frames' default, per access category.
constexpr int kUdpPayloadBytes = 1470;
constexpr int kPings = 200;

// TXTIME of an HT-mixed PPDU at MCS 7, 20 MHz, one stream, 800 ns GI (IEEE 802.11-2016 19.4.3):
// L-STF + L-LTF (16 us), L-SIG (4), HT-SIG (8), HT-STF (4), one HT-LTF (4), then 4 us symbols of
// N_DBPS = 260 bits (Table 19-27) carrying 16 service bits, the PSDU and 6 tail bits.
TimeNs HtMcs7AirtimeNs(int psdu_bytes) {
  const int symbols = (16 + 8 * psdu_bytes + 6 + 259) / 260;
  return (36 + 4 * symbols) * kNsPerUs;
}

// The least time the air can take per best-effort data frame: AIFS[BE] (SIFS + 3 slots), the
// PPDU, SIFS and an ACK at the fastest basic rate (54 Mb/s), no backoff at all. The QoS Data
// header is 2 bytes longer than the DCF's (QoS Control), so the PSDU is the Ethernet frame + 24.
TimeNs LeastBestEffortServiceNs(int udp_payload_bytes) {
  const int ethernet_bytes = udp_payload_bytes + 8 + 20 + 14;
  const TimeNs aifs_be_ns = kOfdmSifsNs + 3 * kOfdmSlotNs;
  return aifs_be_ns + HtMcs7AirtimeNs(ethernet_bytes + kEthernetToPsduBytes + 2) + kOfdmSifsNs +
         OfdmAirtimeNs(kAckBytes, 54);
}

// One ping run's round-trip times, one per request sent: ping's "time=" of each reply (its own
// measure, the kernel's receive stamp minus the send time), and +infinity for every request
// without a reply. Sorted.
std::vector<double> RttsWithLossesMs(const std::string& out, int sent) {
  std::vector<double> rtts;
  const std::regex reply(R"(icmp_seq=\d+ ttl=\d+ time=([0-9.]+) ms)");
  for (auto it = std::sregex_iterator(out.begin(), out.end(), reply); it != std::sregex_iterator();
       ++it) {
    rtts.push_back(std::stod((*it)[1]));
  }
  while (static_cast<int>(rtts.size()) < sent) rtts.push_back(std::numeric_limits<double>::infinity());
  std::sort(rtts.begin(), rtts.end());
  return rtts;
}

// The q-quantile of sorted values: the smallest value at or above a share q of them.
double Quantile(const std::vector<double>& sorted, double q) {
  const size_t rank = static_cast<size_t>(std::ceil(q * sorted.size()));
  return sorted[std::clamp<size_t>(rank, 1, sorted.size()) - 1];
}

uint64_t QueueDrops(MediumScenario& scenario, int robot) {
  return scenario.Counters().station(robot).queue_drops();
}

// Robot b's best-effort queue is full (it drops) while a pings b both ways at once. b's echo
// replies copy the request's TOS (Linux icmp_reply), so the voice reply leaves b through b's
// voice queue and the best-effort reply through the full best-effort queue behind the flood.
// - Voice: the reply waits at most for b's frame on the air, then AIFS[VO] and 3 slots. 99 % of
//   the requests must come back within 5 ms (issue 44's bound), losses counting as infinite.
// - Best effort: a reply finds the queue full (dropped) or joins its tail and waits for the
//   frames ahead, each at least LeastBestEffortServiceNs. The median, losses as infinite, must
//   exceed the time to serve half a full queue at that least service time.
void PingAtVoiceAndBestEffortAcrossAFlood() {
  MediumScenario scenario("qos", 1, kTwoHtRobots);
  scenario.StartDaemon();
  auto server = scenario.Spawn("a", {"iperf3", "-s", "-1", "--forceflush", "-B", scenario.Address(0)});
  ASSERT_TRUE(server->WaitForOutput(false, "Server listening", 10 * kNsPerS)) << server->err();
  // Twice what the air carries with backoff (about 30 Mb/s): the queue overflows all the time.
  const TimeNs service_ns = LeastBestEffortServiceNs(kUdpPayloadBytes);
  auto flood = scenario.Spawn("b", {"iperf3", "-c", scenario.Address(0), "-u", "-b", "62M", "-l",
                                    std::to_string(kUdpPayloadBytes), "-S", "0", "-t", "30"});
  // The flood has filled b's best-effort queue once b's medium queue drops a frame.
  const TimeNs deadline_ns = MonotonicNowNs() + 10 * kNsPerS;
  while (QueueDrops(scenario, 1) == 0 && MonotonicNowNs() < deadline_ns) {
    ASSERT_EQ(flood->Poll(), -1) << "iperf3 client ended early: " << flood->out() << flood->err();
    poll(nullptr, 0, 10);  // Between two looks at the counters; the condition decides, not time.
  }
  const uint64_t drops_before = QueueDrops(scenario, 1);
  ASSERT_GT(drops_before, 0u) << "b's queue never overflowed: " << flood->out() << flood->err();

  const std::string interval = "0.01", wait_s = "1", count = std::to_string(kPings);
  auto voice = scenario.Spawn("a", {PingProgram(), "-n", "-Q", "0xc0", "-c", count, "-i",
                                    interval, "-W", wait_s, scenario.Address(1)});
  auto best_effort = scenario.Spawn("a", {PingProgram(), "-n", "-Q", "0", "-c", count, "-i",
                                          interval, "-W", wait_s, scenario.Address(1)});
  voice->Wait(30 * kNsPerS);
  best_effort->Wait(30 * kNsPerS);
  const uint64_t drops_after = QueueDrops(scenario, 1);
  EXPECT_EQ(flood->Poll(), -1) << "the flood must outlast the pings";
  EXPECT_GT(drops_after, drops_before) << "b's queue overflowed during the pings";

  const std::vector<double> voice_ms = RttsWithLossesMs(voice->out(), kPings);
  const std::vector<double> best_effort_ms = RttsWithLossesMs(best_effort->out(), kPings);
  const double half_queue_ms = kQueueLimitFrames / 2.0 * service_ns / 1e6;
  const auto replies = [](const std::vector<double>& v) {
    return std::count_if(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  std::printf(
      "b's queue drops during the pings: %lu\n"
      "voice (-Q 0xc0): %ld/%d replies, RTT p50 %.3f ms, p99 %.3f ms (bound 5 ms)\n"
      "best effort (-Q 0): %ld/%d replies, RTT p50 %.3f ms (losses infinite; bound: above %.1f ms,"
      " half a %d-frame queue at %.1f us a frame)\n",
      static_cast<unsigned long>(drops_after - drops_before), static_cast<long>(replies(voice_ms)),
      kPings, Quantile(voice_ms, 0.5), Quantile(voice_ms, 0.99),
      static_cast<long>(replies(best_effort_ms)), kPings, Quantile(best_effort_ms, 0.5),
      half_queue_ms, kQueueLimitFrames, service_ns / 1e3);
  EXPECT_GT(Quantile(best_effort_ms, 0.5), half_queue_ms) << best_effort->out();
  // Realtime pacing: three host stalls of 5 ms in the pings' 2 s break the voice bound, whatever
  // the medium did. Such a first run runs once more (realtime_judge.h).
  SCOPED_TRACE(integration_test::kRealtimeBoundMark);
  EXPECT_LT(Quantile(voice_ms, 0.99), 5.0) << voice->out() << voice->err();
}

TEST(TapbridgeQos, VoicePingStaysFastWhileBestEffortFloodsTheLinkAndBestEffortPingDoesNot) {
  SITLNET_REQUIRE_ROOT();
  integration_test::RunOnceMoreIfItFails(PingAtVoiceAndBestEffortAcrossAFlood);
}

}  // namespace
}  // namespace sitlnet::tapbridge::testing
