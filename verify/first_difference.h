// Where two different outputs first differ, in the reader's units (verify-internal).
#ifndef SITLNET_VERIFY_FIRST_DIFFERENCE_H_
#define SITLNET_VERIFY_FIRST_DIFFERENCE_H_

#include <optional>
#include <string>

namespace sitlnet::verify {

// "first at row 17 (time_ns 1234000): ... | ..." for text outputs (CSV, logs, the scenario; a
// .gz one decompressed first), "first at frame 12 (1.234567 s)" for a pcap, "first at byte N"
// otherwise. `path` (relative to the run folder) picks the kind; `a` and `b` must differ.
std::string FirstDifference(const std::string& path, const std::string& a, const std::string& b);

// The gzip stream `bytes` decompressed; nullopt if it is not one whole gzip stream.
std::optional<std::string> Gunzip(const std::string& bytes);

}  // namespace sitlnet::verify

#endif  // SITLNET_VERIFY_FIRST_DIFFERENCE_H_
