// Doppler from the robots' motion for Jakes fading (jakes_doppler_from_speed; not in ns-3,
// whose JakesProcess has one fixed DopplerFrequencyHz, so ns-3 cannot check it).
//
// A station's speed is its last move's distance over the time since the move before (the
// medium only sees positions). A pair's maximum Doppler is f_d = sqrt(v_a^2 + v_b^2) / lambda:
// both ends move through a field of still scatterers. For that case Akki & Haber ("A
// Statistical Model of Mobile-to-Mobile Land Communication Channel", IEEE Trans. Veh. Technol.
// 35(1), 1986) give the autocorrelation J0(2 pi f_a tau) J0(2 pi f_b tau); a Jakes process
// with this f_d has the same curvature at tau = 0, hence the same level-crossing rate and
// average fade duration. The pair's relative speed would be wrong here: two robots flying
// side by side still see their fades change.
//
// The process needs the integral of w_d = 2 pi f_d over time (JakesProcess::
// ComplexGainAtPhase), kept per pair and advanced at each move of either station. At a
// constant speed it is w_d t, as ns-3's.
#ifndef SITLNET_MAC_PHY_SIM_JAKES_DOPPLER_H_
#define SITLNET_MAC_PHY_SIM_JAKES_DOPPLER_H_

#include <vector>

#include "common/common.h"

namespace sitlnet::mac {

class SpeedDoppler {
 public:
  explicit SpeedDoppler(double wavelength_m);

  // Stations in the medium's order, still until they move.
  void AddStation(const Vec3d& position_m, TimeNs at_ns);
  // `station` is at `position_m` from `at_ns` on (not before its last move).
  void Move(int station, const Vec3d& position_m, TimeNs at_ns);

  // The integral of 2 pi f_d of pair (a, b) from its first station's addition to `at_ns`
  // (not before the last move of either), in radians.
  double PhaseRad(int a, int b, TimeNs at_ns) const;
  // The pair's current maximum Doppler, in Hz.
  double DopplerHz(int a, int b) const { return Pair(a, b).doppler_hz; }
  double speed_mps(int station) const { return stations_[station].speed_mps; }

 private:
  struct Station {
    Vec3d position_m;
    TimeNs moved_ns = 0;
    double speed_mps = 0;
  };
  struct PairPhase {
    double phase_rad = 0;  // At since_ns.
    TimeNs since_ns = 0;
    double doppler_hz = 0;  // From since_ns on.
  };
  const PairPhase& Pair(int a, int b) const;
  PairPhase& Pair(int a, int b);

  double wavelength_m_;
  std::vector<Station> stations_;
  std::vector<std::vector<PairPhase>> pairs_;  // Pair (a, b), a < b, at pairs_[b][a].
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_JAKES_DOPPLER_H_
