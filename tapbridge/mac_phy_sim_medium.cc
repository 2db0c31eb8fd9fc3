// MediumModel over mac_phy_sim (the 802.11 DCF simulator), built from the
// scenario. Translates deliveries, counters and the on-air trace.
#include <algorithm>

#include "mac_phy_sim/mac_phy_sim.h"
#include "mac_phy_sim/scenario_adapter.h"
#include "tapbridge/tapbridge.h"

namespace sitlnet::tapbridge {
namespace {

// A detached station is parked this far away: nothing reaches it and it
// reaches no one, without removing it from the medium (ids stay dense).
constexpr double kParkedDistanceM = 1e9;

class MacPhySimMedium : public MediumModel {
 public:
  explicit MacPhySimMedium(const Scenario& scenario)
      : medium_(mac::MakeMediumFromScenario(scenario)) {
    for (const RobotPlan& robot : scenario.robots) {
      const auto& p = robot.spec.position_m();
      positions_.push_back(Vec3d{p.x(), p.y(), p.z()});
    }
    enabled_.assign(positions_.size(), true);
    macs_.resize(positions_.size());
    for (const RobotPlan& robot : scenario.robots) macs_[robot.index] = robot.wlan_mac;
  }

  void Submit(int station, TimeNs at_ns, std::span<const uint8_t> ethernet) override {
    if (!enabled_[station]) return;
    medium_.SubmitFrame(station, ethernet, at_ns);
  }

  void AdvanceTo(TimeNs until_ns, std::vector<Delivery>* deliveries,
                 std::vector<AirFrame>* air) override {
    if (until_ns < medium_.now_ns()) until_ns = medium_.now_ns();
    // Tracing records every transmission and its receptions: on only while someone captures.
    if (air != nullptr && !tracing_) {
      medium_.EnableTrace(true);
      tracing_ = true;
    } else if (air == nullptr && tracing_ && !sink_) {
      trace_.clear();
      medium_.DrainTrace(&trace_);
      medium_.EnableTrace(false);
      tracing_ = false;
    }
    scratch_.clear();
    medium_.AdvanceTo(until_ns, &scratch_);
    for (mac::Delivery& d : scratch_) {
      if (!enabled_[d.station]) continue;
      deliveries->push_back(std::move(d));
    }
    if (tracing_) {
      trace_.clear();
      medium_.DrainTrace(&trace_);
      if (air != nullptr) {
        for (mac::TraceEvent& event : trace_) {
          if (sink_) sink_(event);
          if (event.tx) air->push_back(ToAirFrame(std::move(*event.tx)));
        }
      } else if (sink_) {
        for (const mac::TraceEvent& event : trace_) sink_(event);
      }
    }
  }

  std::optional<TimeNs> NextEventNs() const override { return medium_.NextEventNs(); }

  void SetPosition(int station, double x_m, double y_m, double z_m) override {
    positions_[station] = Vec3d{x_m, y_m, z_m};
    if (enabled_[station]) {
      medium_.SetStationPosition(station, positions_[station], medium_.now_ns());
    }
  }

  void SetStationEnabled(int station, bool enabled) override {
    if (enabled_[station] == enabled) return;
    enabled_[station] = enabled;
    const Vec3d parked{kParkedDistanceM * (station + 1), kParkedDistanceM, 0};
    medium_.SetStationPosition(station, enabled ? positions_[station] : parked, medium_.now_ns());
  }

  MediumCounters Counters(int station) const override {
    const mac::StationCounters& c = medium_.counters(station);
    MediumCounters out;
    out.sent = c.frames_submitted;
    out.delivered = c.rx_delivered;
    out.queue_drops = c.queue_drops;
    out.queue_expired = c.queue_expired;
    out.lost = {{"retry_limit", c.lost_retry_limit},
                {"malformed", c.malformed},
                {"rx_collided", c.rx_collided},
                {"rx_error", c.rx_error},
                {"rx_below_sensitivity", c.rx_below_sensitivity}};
    out.other = {{"sent_ok", c.sent_ok}, {"data_tx", c.data_tx},
                 {"retries", c.retries}, {"tx_failures", c.tx_failures},
                 {"ack_tx", c.ack_tx},   {"rts_tx", c.rts_tx},
                 {"cts_tx", c.cts_tx},   {"rx_duplicates", c.rx_duplicates}};
    return out;
  }

  size_t MaxEthernetFrameBytes() const override { return kMax80211EthernetFrameBytes; }

  void SetTraceSink(std::function<void(const mac::TraceEvent&)> sink) override {
    sink_ = std::move(sink);
    medium_.EnableTrace(true);
    medium_.EnableCauses(true);
    tracing_ = true;
  }

 private:
  int StationOf(const MacAddress& mac) const {
    for (size_t i = 0; i < macs_.size(); ++i) {
      if (macs_[i] == mac) return static_cast<int>(i);
    }
    return -1;
  }

  AirFrame ToAirFrame(mac::TxRecord&& tx) const {
    AirFrame f;
    const mac::PhyInfo& phy = medium_.phy();
    f.channel_mhz = static_cast<int>(phy.frequency_mhz + 0.5);
    f.band_5ghz = phy.frequency_mhz > 4000;
    f.ofdm = medium_.config().standard != mac::Standard::k80211b;
    f.noise_dbm = phy.noise_floor_dbm;
    // Signal: at the addressed receiver; for group frames, the strongest.
    // Failed (bad FCS): the addressed receiver did not decode it; a group
    // frame that nobody decoded.
    const int addressed = tx.receiver.IsGroup() ? -1 : StationOf(tx.receiver);
    const mac::RxRecord* shown = nullptr;
    bool anyone_received = false;
    for (const mac::RxRecord& rx : tx.receptions) {
      if (rx.outcome == mac::RxOutcome::kReceived) anyone_received = true;
      if (addressed >= 0) {
        if (rx.station == addressed) shown = &rx;
      } else if (shown == nullptr || rx.rx_power_dbm > shown->rx_power_dbm) {
        shown = &rx;
      }
    }
    if (shown != nullptr) {
      f.signal_dbm = shown->rx_power_dbm;
      f.failed = addressed >= 0 ? shown->outcome != mac::RxOutcome::kReceived : !anyone_received;
    } else {
      f.signal_dbm = -100;
    }
    f.tx = std::move(tx);
    f.tx.receptions.clear();  // Summarised above; the pcap view does not need them.
    return f;
  }

  mutable mac::Medium medium_;  // NextEventNs is not const in mac_phy_sim.
  std::vector<Vec3d> positions_;
  std::vector<bool> enabled_;
  std::vector<MacAddress> macs_;
  std::vector<mac::Delivery> scratch_;
  std::vector<mac::TraceEvent> trace_;
  bool tracing_ = false;
  std::function<void(const mac::TraceEvent&)> sink_;  // SetTraceSink: causes recorded.
};

}  // namespace

std::unique_ptr<MediumModel> MakeMacPhySimMedium(const Scenario& scenario) {
  return std::make_unique<MacPhySimMedium>(scenario);
}

}  // namespace sitlnet::tapbridge
