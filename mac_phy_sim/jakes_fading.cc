#include "mac_phy_sim/jakes_fading.h"

#include <algorithm>

namespace sitlnet::mac {

JakesFading::JakesFading(const JakesParameters& parameters, uint64_t seed)
    : parameters_(parameters), seed_(seed) {}

const JakesProcess& JakesFading::Process(int a, int b) {
  SITLNET_DEMAND(a != b && a >= 0 && b >= 0);
  const uint64_t key =
      (static_cast<uint64_t>(std::min(a, b)) << 32) | static_cast<uint64_t>(std::max(a, b));
  auto it = processes_.find(key);
  if (it == processes_.end()) {
    RandomEngine rng(SplitMix64(seed_ ^ SplitMix64(key)));
    it = processes_.emplace(key, JakesProcess(parameters_, rng)).first;
  }
  return it->second;
}

double JakesFading::PowerGainDb(int a, int b, TimeNs at_ns) {
  return Process(a, b).PowerGainDb(at_ns);
}

}  // namespace sitlnet::mac
