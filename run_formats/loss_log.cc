#include "run_formats/run_formats.h"

#include <zlib.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <utility>

#include "mac_phy_sim/scenario_adapter.h"

namespace sitlnet::run_formats {
namespace {

constexpr size_t kDeflateInputBytes = 1 << 16;  // CSV text gathered before each deflate call.
constexpr size_t kChunkBytes = 1 << 16;

const char* KindName(mac::FrameKind kind) {
  switch (kind) {
    case mac::FrameKind::kData:
      return "DATA";
    case mac::FrameKind::kAck:
      return "ACK";
    case mac::FrameKind::kRts:
      return "RTS";
    case mac::FrameKind::kCts:
      return "CTS";
    case mac::FrameKind::kCfEnd:
      return "CF-End";
    case mac::FrameKind::kBlockAck:
      return "BlockAck";
    case mac::FrameKind::kBlockAckReq:
      return "BlockAckReq";
    case mac::FrameKind::kAction:
      return "Action";
  }
  return "?";
}

// Losses counted per link in links.csv.
enum Loss : int {
  kObstacle,
  kRange,
  kNoiseError,
  kCollision,
  kAlreadyReceiving,
  kOwnTransmission,
  kRetryLimit,
  kQueueFull,
  kQueueExpired,
  kLossKinds
};
// links.csv's main_cause words: below_threshold split by whether the obstacles decided it.
constexpr std::array<const char*, kLossKinds> kLossNames = {
    "obstacle",         "range",       "noise_error", "collision",    "already_receiving",
    "own_transmission", "retry_limit", "queue_full",  "queue_expired"};

// Appends ',' and the integer.
void Int(std::string& out, long long value) {
  char digits[24];
  out += ',';
  out.append(digits, std::to_chars(digits, digits + sizeof digits, value).ptr);
}

// Appends ',' and `value` with one decimal (as %.1f but for ties and -0; empty if not finite):
// the row is formatted on the medium's thread, and snprintf of four doubles cost more than
// everything else the row needs.
void Decibel(std::string& out, double value) {
  out += ',';
  if (!std::isfinite(value)) return;
  const long long tenths = std::llround(value * 10);
  const unsigned long long magnitude = tenths < 0 ? -tenths : tenths;
  if (tenths < 0) out += '-';
  char digits[24];
  out.append(digits, std::to_chars(digits, digits + sizeof digits, magnitude / 10).ptr);
  out += '.';
  out += static_cast<char>('0' + magnitude % 10);
}

}  // namespace

const char* CauseName(mac::RxCause cause) {
  switch (cause) {
    case mac::RxCause::kUnknown:
      return "unknown";
    case mac::RxCause::kDecoded:
      return "decoded";
    case mac::RxCause::kBelowThreshold:
      return "below_threshold";
    case mac::RxCause::kNoiseError:
      return "noise_error";
    case mac::RxCause::kCollision:
      return "collision";
    case mac::RxCause::kAlreadyReceiving:
      return "already_receiving";
    case mac::RxCause::kOwnTransmission:
      return "own_transmission";
  }
  return "?";
}

const char* DropName(mac::DropReason reason) {
  switch (reason) {
    case mac::DropReason::kRetryLimit:
      return "retry_limit";
    case mac::DropReason::kQueueFull:
      return "queue_full";
    case mac::DropReason::kQueueExpired:
      return "queue_expired";
  }
  return "?";
}

struct LossLog::Counts {
  uint64_t frames = 0, delivered = 0;
  std::array<uint64_t, kLossKinds> losses{};
  double rate_mbps = 0;  // Of the last DATA frame counted.
  int mcs = -1;
};

struct LossLog::ZStream {
  z_stream z{};
};

LossLog::LossLog(const std::string& run_dir, std::vector<MacAddress> stations,
                 double noise_floor_dbm, double detect_min_rssi_dbm)
    : run_dir_(run_dir),
      stations_(std::move(stations)),
      noise_floor_dbm_(noise_floor_dbm),
      detect_min_rssi_dbm_(detect_min_rssi_dbm),
      file_(std::make_unique<LineFile>(run_dir + "/losses.csv.gz", "", 4, "losses")),
      z_(std::make_unique<ZStream>()) {
  // windowBits 15 + 16: a gzip stream (zcat, Python's gzip read it). Level 1 (Z_BEST_SPEED):
  // deflate is most of the file's cost, and level 1 halves it for a file 35 % larger, still
  // smaller than medium.pcap (docs/performance.md, "Loss recording").
  if (deflateInit2(&z_->z, Z_BEST_SPEED, Z_DEFLATED, 15 + 16, 8,
                   Z_DEFAULT_STRATEGY) != Z_OK) {
    throw Error("losses.csv.gz: zlib deflateInit2 failed");
  }
  pending_.reserve(kDeflateInputBytes + 256);
  pending_ += kLossHeader;
  pending_ += '\n';
}

LossLog::~LossLog() {
  if (finished_) return;
  try {
    Finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sitlnet: %s\n", e.what());
  }
  if (!finished_) deflateEnd(&z_->z);
}

int LossLog::StationOf(const MacAddress& mac) const {
  if (mac.IsGroup()) return -1;
  const auto it = std::find(stations_.begin(), stations_.end(), mac);
  return it == stations_.end() ? -1 : static_cast<int>(it - stations_.begin());
}

LossLog::Counts& LossLog::Link(TimeNs time_ns, int from, int to) {
  const uint64_t key = static_cast<uint64_t>(time_ns / kNsPerS) << 32 |
                       static_cast<uint64_t>(from + 1) << 16 | static_cast<uint64_t>(to + 1);
  const auto [it, made] = links_.try_emplace(key);
  if (made && live_ != nullptr) live_keys_.push_back(key);
  return it->second;
}

LinkRow LossLog::RowOf(uint64_t key, const Counts& c) {
  LinkRow row;
  row.second = static_cast<int64_t>(key >> 32);
  row.from = static_cast<int>((key >> 16) & 0xffff) - 1;
  row.to = static_cast<int>(key & 0xffff) - 1;
  row.frames = c.frames;
  row.delivered = c.delivered;
  const auto main = std::max_element(c.losses.begin(), c.losses.end());
  row.main_cause_frames = *main;
  if (*main > 0) row.main_cause = kLossNames[main - c.losses.begin()];
  row.rate_mbps = c.rate_mbps;
  row.mcs = c.mcs;
  return row;
}

void LossLog::PublishSecondsBefore(TimeNs time_ns) {
  constexpr TimeNs kOnAirMarginNs = 50 * kNsPerMs;
  while (live_ != nullptr && time_ns >= (next_live_second_ + 1) * kNsPerS + kOnAirMarginNs) {
    std::vector<LinkRow> rows;
    std::vector<uint64_t> later;
    for (const uint64_t key : live_keys_) {
      const int64_t second = static_cast<int64_t>(key >> 32);
      if (second == next_live_second_) rows.push_back(RowOf(key, links_.at(key)));
      else if (second > next_live_second_) later.push_back(key);
    }
    std::sort(rows.begin(), rows.end(), [](const LinkRow& a, const LinkRow& b) {
      return std::pair(a.from, a.to) < std::pair(b.from, b.to);
    });
    live_keys_ = std::move(later);
    live_->Links(next_live_second_++, rows);
  }
}

void LossLog::Deflate(int flush) {
  z_->z.next_in = reinterpret_cast<Bytef*>(pending_.data());
  z_->z.avail_in = static_cast<uInt>(pending_.size());
  std::array<unsigned char, kChunkBytes> out;
  int status;
  do {
    z_->z.next_out = out.data();
    z_->z.avail_out = static_cast<uInt>(out.size());
    status = deflate(&z_->z, flush);
    if (status == Z_STREAM_ERROR) throw Error("losses.csv.gz: zlib deflate failed");
    const size_t produced = out.size() - z_->z.avail_out;
    if (produced > 0) {
      file_->AppendRecord({reinterpret_cast<const char*>(out.data()), produced});
    }
  } while (z_->z.avail_out == 0 || (flush == Z_FINISH && status != Z_STREAM_END));
  pending_.clear();
}

void LossLog::Add(const mac::TraceEvent& event) {
  if (event.drop) {
    const mac::DropRecord& d = *event.drop;
    const int to = StationOf(d.destination);
    // A frame dropped before it was given a sequence number has none: the field stays empty.
    char sequence[8] = "";
    if (d.has_sequence_number) std::snprintf(sequence, sizeof sequence, "%u", d.sequence_number);
    char row[160];
    const int n = std::snprintf(row, sizeof row, "%lld,%d,%d,DATA,%s,,%d,%s,,,,,\n",
                                static_cast<long long>(d.time_ns), d.station, to, sequence,
                                d.station, DropName(d.reason));
    pending_.append(row, static_cast<size_t>(n));
    Counts& c = Link(d.time_ns, d.station, to);
    ++c.losses[d.reason == mac::DropReason::kRetryLimit  ? kRetryLimit
               : d.reason == mac::DropReason::kQueueFull ? kQueueFull
                                                         : kQueueExpired];
  } else if (event.tx) {
    AddTransmission(*event.tx);
  }
  if (pending_.size() >= kDeflateInputBytes) Deflate(Z_NO_FLUSH);
  if (live_ != nullptr) PublishSecondsBefore(event.drop ? event.drop->time_ns : event.tx->start_ns);
}

void LossLog::AddTransmission(const mac::TxRecord& tx) {
  const int to = StationOf(tx.receiver);
  const bool data = tx.kind == mac::FrameKind::kData;
  // The columns every row of this transmission shares, up to `station`.
  char head[96];
  const int head_length = std::snprintf(head, sizeof head, "%lld,%d,%d,%s,%u,%d",
                                        static_cast<long long>(tx.start_ns), tx.source, to,
                                        KindName(tx.kind), tx.sequence_number, tx.retry ? 1 : 0);
  for (const mac::RxRecord& r : tx.receptions) {
    if (!(r.rx_power_dbm >= noise_floor_dbm_)) continue;
    pending_.append(head, static_cast<size_t>(head_length));
    Int(pending_, r.station);
    pending_ += ',';
    pending_ += CauseName(r.cause);
    Int(pending_, r.interferer);
    Decibel(pending_, r.rx_power_dbm);
    Decibel(pending_, r.sinr_db);
    // The loss split only where the signal's weakness decided (half the bytes otherwise).
    if (r.cause == mac::RxCause::kBelowThreshold || r.cause == mac::RxCause::kNoiseError) {
      Decibel(pending_, r.path_loss_db);
      Decibel(pending_, r.obstacle_loss_db);
    } else {
      pending_ += ",,";
    }
    pending_ += '\n';
    // links.csv: DATA frames at the station they are for (every station for a group frame).
    if (!data || (to >= 0 && r.station != to) || (to < 0 && !tx.receiver.IsGroup())) continue;
    Counts& c = Link(tx.start_ns, tx.source, r.station);
    ++c.frames;
    DeliveryCounts& by_class =
        r.obstructed ? by_link_class_.obstructed : by_link_class_.line_of_sight;
    ++by_class.frames;
    if (r.cause == mac::RxCause::kDecoded) ++by_class.delivered;
    c.rate_mbps = tx.rate_mbps;
    c.mcs = tx.mcs;
    switch (r.cause) {
      case mac::RxCause::kDecoded:
        ++c.delivered;
        break;
      case mac::RxCause::kBelowThreshold:
        ++c.losses[r.rx_power_dbm + r.obstacle_loss_db >= detect_min_rssi_dbm_ ? kObstacle
                                                                                : kRange];
        break;
      case mac::RxCause::kNoiseError:
        ++c.losses[kNoiseError];
        break;
      case mac::RxCause::kCollision:
        ++c.losses[kCollision];
        break;
      case mac::RxCause::kAlreadyReceiving:
        ++c.losses[kAlreadyReceiving];
        break;
      case mac::RxCause::kOwnTransmission:
        ++c.losses[kOwnTransmission];
        break;
      case mac::RxCause::kUnknown:
        break;
    }
  }
}

void LossLog::Finish() {
  if (finished_) return;
  finished_ = true;
  Deflate(Z_FINISH);
  deflateEnd(&z_->z);
  file_->Flush();
  file_.reset();
  LineFile links(run_dir_ + "/links.csv", kLinkHeader, 256, "links");
  std::vector<std::pair<uint64_t, const Counts*>> sorted;
  sorted.reserve(links_.size());
  for (const auto& [key, c] : links_) sorted.emplace_back(key, &c);
  // By second, then from, then to (-1 first): the key's order.
  std::sort(sorted.begin(), sorted.end(),
            [](const auto& a, const auto& b) { return a.first < b.first; });
  if (!sorted.empty()) {  // The last seconds, to the live view.
    PublishSecondsBefore(static_cast<TimeNs>((sorted.back().first >> 32) + 2) * kNsPerS);
  }
  std::string line;
  for (const auto& [key, counts] : sorted) {
    const LinkRow row = RowOf(key, *counts);
    char head[160];
    const int n = std::snprintf(head, sizeof head, "%lld,%d,%d,%llu,%llu,",
                                static_cast<long long>(row.second), row.from, row.to,
                                static_cast<unsigned long long>(row.frames),
                                static_cast<unsigned long long>(row.delivered));
    line.assign(head, static_cast<size_t>(n));
    if (row.frames > 0) {
      char ratio[32];
      std::snprintf(ratio, sizeof ratio, "%.3f",
                    static_cast<double>(row.delivered) / static_cast<double>(row.frames));
      line += ratio;
    }
    line += ',';
    line += row.main_cause;
    line += ',';
    line += std::to_string(row.main_cause_frames);
    char rate[48];
    std::snprintf(rate, sizeof rate, ",%g,", row.rate_mbps);
    line += rate;
    if (row.mcs >= 0) line += std::to_string(row.mcs);
    links.Append(line);
  }
  links.Flush();
}

std::unique_ptr<LossLog> MakeLossLog(const std::string& run_dir, const Scenario& scenario) {
  std::vector<MacAddress> macs(scenario.robots.size());
  for (const RobotPlan& robot : scenario.robots) macs[robot.index] = robot.wlan_mac;
  const mac::MediumConfig config = mac::MediumConfigFromScenario(scenario);
  return std::make_unique<LossLog>(run_dir, std::move(macs),
                                   mac::DerivePhyInfo(config).noise_floor_dbm,
                                   config.preamble_detect_min_rssi_dbm);
}

}  // namespace sitlnet::run_formats
