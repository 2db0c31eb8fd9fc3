// Lockstep pacing spreads the frames a robot wrote during a step over the step, at instants
// drawn from a generator of its own (docs/tapbridge.md, "Lockstep"). This is that generator.
#ifndef SITLNET_TAPBRIDGE_LOCKSTEP_SPREAD_H_
#define SITLNET_TAPBRIDGE_LOCKSTEP_SPREAD_H_

#include <cstdint>
#include <random>

namespace sitlnet::tapbridge {

// Robot `robot`'s stream of intra-step offsets for a run seeded with `run_seed` (all 64 bits).
inline std::mt19937_64 LockstepSpreadStream(uint64_t run_seed, uint64_t robot) {
  // std::seed_seq keeps only the low 32 bits of each value it is given, so the seed goes in as
  // two halves. The high half is appended only when it is not zero: seeds below 2^32 (every
  // seed used before the high half counted) keep the streams, and so the outputs, they had.
  const auto low = static_cast<uint32_t>(run_seed);
  const auto high = static_cast<uint32_t>(run_seed >> 32);
  if (high == 0) {
    std::seed_seq seq{uint64_t{low}, robot, uint64_t{0x7a9b}};
    return std::mt19937_64(seq);
  }
  std::seed_seq seq{uint64_t{low}, robot, uint64_t{0x7a9b}, uint64_t{high}};
  return std::mt19937_64(seq);
}

}  // namespace sitlnet::tapbridge

#endif  // SITLNET_TAPBRIDGE_LOCKSTEP_SPREAD_H_
