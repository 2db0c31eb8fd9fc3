// Which vehicle a GCS's frame is for: the target_system field of the messages that have one, at
// the offsets MAVLink's definitions give (generated at build time, target_fields_gen.cjs).
#ifndef SITLNET_GCS_LINK_MESSAGE_TARGET_H_
#define SITLNET_GCS_LINK_MESSAGE_TARGET_H_

#include <cstddef>
#include <cstdint>
#include <optional>

namespace sitlnet::gcs {

// The target system of the whole MAVLink 1 or 2 frame at `frame`: nullopt if its message has no
// target_system field (or the table is empty, built without mavlink-mappings); 0 means every
// system (MAVLink's broadcast). A field cut off by MAVLink 2's zero truncation reads 0.
std::optional<uint8_t> TargetSystem(const uint8_t* frame);

// How many messages the generated table holds (0: built without mavlink-mappings).
size_t TargetTableSize();

}  // namespace sitlnet::gcs

#endif  // SITLNET_GCS_LINK_MESSAGE_TARGET_H_
