// The no-medium floor: a plain relay that delivers each frame at the instant
// it was submitted. Used by the benchmark to separate the bridge's own cost
// (TAP I/O, event loop, pacing) from the 802.11 model's.
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

class RelayMedium : public MediumModel {
 public:
  explicit RelayMedium(const std::vector<MacAddress>& macs)
      : macs_(macs), enabled_(macs.size(), true), counters_(macs.size()) {}

  void Submit(int station, TimeNs at_ns, std::span<const uint8_t> ethernet) override {
    if (!enabled_[station] || ethernet.size() < 14) return;
    ++counters_[station].sent;
    MacAddress destination;
    std::copy(ethernet.begin(), ethernet.begin() + 6, destination.bytes.begin());
    for (size_t i = 0; i < macs_.size(); ++i) {
      if (static_cast<int>(i) == station || !enabled_[i]) continue;
      if (!destination.IsGroup() && !(macs_[i] == destination)) continue;
      pending_.push_back(Delivery{static_cast<int>(i), station,
                                  std::vector<uint8_t>(ethernet.begin(), ethernet.end()), at_ns, 0,
                                  0});
      ++counters_[i].delivered;
    }
  }
  void AdvanceTo(TimeNs until_ns, std::vector<Delivery>* deliveries,
                 std::vector<AirFrame>* air) override {
    for (Delivery& d : pending_) deliveries->push_back(std::move(d));
    pending_.clear();
  }
  std::optional<TimeNs> NextEventNs() const override {
    if (pending_.empty()) return std::nullopt;
    return pending_.front().delivery_ns;
  }
  void SetPosition(int, double, double, double) override {}
  void SetStationEnabled(int station, bool enabled) override { enabled_[station] = enabled; }
  MediumCounters Counters(int station) const override { return counters_[station]; }
  size_t MaxEthernetFrameBytes() const override { return kMax80211EthernetFrameBytes; }

 private:
  std::vector<MacAddress> macs_;
  std::vector<bool> enabled_;
  std::vector<MediumCounters> counters_;
  std::vector<Delivery> pending_;
};

}  // namespace

std::unique_ptr<MediumModel> MakeRelayMedium(const std::vector<MacAddress>& station_macs) {
  return std::make_unique<RelayMedium>(station_macs);
}

}  // namespace sitlnet::tapbridge
