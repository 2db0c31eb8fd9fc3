#include "gcs_link/message_target.h"

#include <algorithm>
#include <iterator>

#include "mavlink/mavlink.h"

namespace sitlnet::gcs {
namespace {

struct TargetFields {
  uint32_t message_id;
  int system_offset;
  int component_offset;
};

constexpr TargetFields kTargetFields[] = {
#include "gcs_link/target_fields.inc"
    {0xFFFFFFFF, -1, -1},  // An end that no message id reaches (the table may be empty).
};

}  // namespace

std::optional<uint8_t> TargetSystem(const uint8_t* frame) {
  const bool v1 = frame[0] == mavlink::kMagicV1;
  const uint32_t id =
      v1 ? frame[5] : frame[7] | (frame[8] << 8) | (static_cast<uint32_t>(frame[9]) << 16);
  const TargetFields* found = std::lower_bound(
      std::begin(kTargetFields), std::end(kTargetFields), id,
      [](const TargetFields& entry, uint32_t key) { return entry.message_id < key; });
  if (found->message_id != id) return std::nullopt;
  const size_t payload_bytes = frame[1];
  const uint8_t* payload = frame + (v1 ? mavlink::kHeaderV1Bytes : mavlink::kHeaderV2Bytes);
  const size_t offset = static_cast<size_t>(found->system_offset);
  return offset < payload_bytes ? payload[offset] : 0;
}

size_t TargetTableSize() { return std::size(kTargetFields) - 1; }

}  // namespace sitlnet::gcs
