#include "mac_phy_sim/jakes_doppler.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace sitlnet::mac {

SpeedDoppler::SpeedDoppler(double wavelength_m) : wavelength_m_(wavelength_m) {
  SITLNET_DEMAND(wavelength_m > 0);
}

void SpeedDoppler::AddStation(const Vec3d& position_m, TimeNs at_ns) {
  stations_.push_back({position_m, at_ns, 0});
  pairs_.emplace_back(stations_.size() - 1, PairPhase{0, at_ns, 0});
}

void SpeedDoppler::Move(int station, const Vec3d& position_m, TimeNs at_ns) {
  Station& st = stations_[station];
  SITLNET_DEMAND(at_ns >= st.moved_ns);
  if (at_ns == st.moved_ns) {  // A second move at the same instant: no time to measure over.
    st.position_m = position_m;
    return;
  }
  const double dx = position_m.x - st.position_m.x, dy = position_m.y - st.position_m.y,
               dz = position_m.z - st.position_m.z;
  const double speed_mps = std::sqrt(dx * dx + dy * dy + dz * dz) / ((at_ns - st.moved_ns) / 1e9);
  // A position that is not a number leaves the speed as it was.
  if (std::isfinite(speed_mps)) st.speed_mps = speed_mps;
  st.position_m = position_m;
  st.moved_ns = at_ns;
  // Every pair of the station: the row below it, then the column above (the hot loop of a
  // fleet that moves every step: no checks, no calls).
  const double speed2 = st.speed_mps * st.speed_mps;
  const double inverse_wavelength = 1 / wavelength_m_;
  auto advance = [&](PairPhase& pair, double other_speed_mps) {
    pair.phase_rad += 2 * std::numbers::pi * pair.doppler_hz * ((at_ns - pair.since_ns) / 1e9);
    pair.since_ns = at_ns;
    pair.doppler_hz = std::sqrt(speed2 + other_speed_mps * other_speed_mps) * inverse_wavelength;
  };
  std::vector<PairPhase>& row = pairs_[station];
  for (int other = 0; other < station; ++other) advance(row[other], stations_[other].speed_mps);
  for (int other = station + 1; other < static_cast<int>(stations_.size()); ++other) {
    advance(pairs_[other][station], stations_[other].speed_mps);
  }
}

double SpeedDoppler::PhaseRad(int a, int b, TimeNs at_ns) const {
  const PairPhase& pair = Pair(a, b);
  return pair.phase_rad +
         2 * std::numbers::pi * pair.doppler_hz * ((at_ns - pair.since_ns) / 1e9);
}

const SpeedDoppler::PairPhase& SpeedDoppler::Pair(int a, int b) const {
  SITLNET_DEMAND(a != b);
  return pairs_[std::max(a, b)][std::min(a, b)];
}

SpeedDoppler::PairPhase& SpeedDoppler::Pair(int a, int b) {
  SITLNET_DEMAND(a != b);
  return pairs_[std::max(a, b)][std::min(a, b)];
}

}  // namespace sitlnet::mac
