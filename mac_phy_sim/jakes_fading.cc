#include "mac_phy_sim/jakes_fading.h"

#include <algorithm>

namespace sitlnet::mac {

JakesFading::JakesFading(const JakesParameters& parameters, uint64_t seed)
    : parameters_(parameters), seed_(seed) {}

const JakesProcess& JakesFading::Process(int a, int b) {
  SITLNET_DEMAND(a != b && a >= 0 && b >= 0);
  const int low = std::min(a, b), high = std::max(a, b);
  while (static_cast<int>(slot_.size()) <= high) slot_.emplace_back(slot_.size(), -1);
  int32_t& slot = slot_[high][low];
  if (slot < 0) {
    const uint64_t key = (static_cast<uint64_t>(low) << 32) | static_cast<uint64_t>(high);
    RandomEngine rng(SplitMix64(seed_ ^ SplitMix64(key)));
    slot = static_cast<int32_t>(processes_.size());
    processes_.emplace_back(parameters_, rng);
  }
  return processes_[slot];
}

double JakesFading::PowerGainDb(int a, int b, TimeNs at_ns) {
  return Process(a, b).PowerGainDb(at_ns);
}

double JakesFading::PowerGainDbAtPhase(int a, int b, double doppler_phase_rad) {
  return Process(a, b).PowerGainDbAtPhase(doppler_phase_rad);
}

}  // namespace sitlnet::mac
