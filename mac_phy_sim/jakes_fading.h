// Jakes fading over a fleet: one JakesProcess per unordered station pair, created the first
// time the pair's power is asked for. ns-3's JakesPropagationLossModel keys its processes by
// the pair of mobility models in a PropagationCache whose key ignores the order ("links are
// supposed to be symmetrical"): a -> b and b -> a share one process, and so they do here.
// ns-3 draws each new process's angles from one shared stream, in the order pairs are first
// used; here each pair has a stream of its own, from the seed and the pair alone, so a process
// does not depend on which links were used before it (reproducible under any traffic).
#ifndef SITLNET_MAC_PHY_SIM_JAKES_FADING_H_
#define SITLNET_MAC_PHY_SIM_JAKES_FADING_H_

#include <cstdint>
#include <vector>

#include "mac_phy_sim/jakes_process.h"

namespace sitlnet::mac {

class JakesFading {
 public:
  // `seed`: the medium's fading seed (derived from MediumConfig::seed, apart from the MAC's).
  JakesFading(const JakesParameters& parameters, uint64_t seed);

  // The power gain of pair (a, b) at `at_ns` in dB (JakesProcess::PowerGainDb); a != b.
  double PowerGainDb(int a, int b, TimeNs at_ns);
  // The same at a Doppler phase instead of a time (SpeedDoppler::PhaseRad).
  double PowerGainDbAtPhase(int a, int b, double doppler_phase_rad);
  // The pair's process, created on first use.
  const JakesProcess& Process(int a, int b);
  // Processes created so far (memory follows the pairs used, not stations^2).
  size_t process_count() const { return processes_.size(); }

 private:
  JakesParameters parameters_;
  uint64_t seed_;
  std::vector<JakesProcess> processes_;
  // Index into processes_ of pair (a, b), a < b, at slot_[b][a]; -1: not created yet. A
  // triangle that grows with the highest station asked for (a hash map cost 7 % of a frame).
  std::vector<std::vector<int32_t>> slot_;
};

}  // namespace sitlnet::mac

#endif  // SITLNET_MAC_PHY_SIM_JAKES_FADING_H_
