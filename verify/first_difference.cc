#include "verify/first_difference.h"

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>

namespace sitlnet::verify {
namespace {

bool EndsWith(const std::string& text, const std::string& end) {
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

size_t Mismatch(const std::string& a, const std::string& b) {
  return static_cast<size_t>(std::mismatch(a.begin(), a.begin() + std::min(a.size(), b.size()),
                                            b.begin())
                                 .first -
                             a.begin());
}

// The line of `text` that holds byte `at` (without its newline), cut to a readable length.
std::string LineAt(const std::string& text, size_t at) {
  if (at >= text.size()) return "(end of file)";
  const size_t begin = at == 0 ? 0 : text.rfind('\n', at - 1) + 1;
  const size_t end = std::min(text.find('\n', at), text.size());
  std::string line = text.substr(begin, std::min<size_t>(end - begin, 72));
  return "\"" + line + (end - begin > 72 ? "...\"" : "\"");
}

std::string FirstField(const std::string& text, size_t line_begin) {
  const size_t end = text.find_first_of(",\n", line_begin);
  return text.substr(line_begin, (end == std::string::npos ? text.size() : end) - line_begin);
}

std::string TextDifference(const std::string& a, const std::string& b, bool csv) {
  const size_t at = Mismatch(a, b);
  const long row = std::count(a.begin(), a.begin() + static_cast<long>(at), '\n') + 1;
  std::string where = "first at line " + std::to_string(row);
  // A CSV's first column is its time (time_s, time_ns, second) or an iteration: name it.
  if (csv && row > 1) {
    const size_t line_begin = at == 0 ? 0 : a.rfind('\n', at - 1) + 1;
    where = "first at row " + std::to_string(row - 1) + " (" + FirstField(a, 0) + " " +
            FirstField(a, line_begin) + ")";
  }
  return where + ": " + LineAt(a, at) + " vs " + LineAt(b, at);
}

uint32_t Le32(const std::string& bytes, size_t at) {
  return static_cast<uint32_t>(static_cast<uint8_t>(bytes[at])) |
         static_cast<uint32_t>(static_cast<uint8_t>(bytes[at + 1])) << 8 |
         static_cast<uint32_t>(static_cast<uint8_t>(bytes[at + 2])) << 16 |
         static_cast<uint32_t>(static_cast<uint8_t>(bytes[at + 3])) << 24;
}

// The first record (from 1) of two pcaps that differs, with its timestamp (virtual in lockstep).
std::string PcapDifference(const std::string& a, const std::string& b) {
  const size_t at = Mismatch(a, b);
  if (at < 24) return "first in the file header (byte " + std::to_string(at) + ")";
  size_t record = 24;
  long frame = 1;
  while (record + 16 <= a.size()) {
    const size_t end = record + 16 + Le32(a, record + 8);
    if (at < end || end > a.size()) break;
    record = end;
    ++frame;
  }
  if (record + 16 > a.size()) {
    return "frame " + std::to_string(frame) + " on is in one capture only";
  }
  char when[64];
  std::snprintf(when, sizeof when, "%u.%06u s", Le32(a, record), Le32(a, record + 4));
  return "first at frame " + std::to_string(frame) + " (" + when + "), byte " +
         std::to_string(at - record - 16) + " of its record";
}

}  // namespace

std::optional<std::string> Gunzip(const std::string& bytes) {
  z_stream stream{};
  if (inflateInit2(&stream, 16 + MAX_WBITS) != Z_OK) return std::nullopt;
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(bytes.data()));
  stream.avail_in = static_cast<uInt>(bytes.size());
  std::string out;
  char block[1 << 16];
  int status = Z_OK;
  while (status == Z_OK) {
    stream.next_out = reinterpret_cast<Bytef*>(block);
    stream.avail_out = sizeof block;
    status = inflate(&stream, Z_NO_FLUSH);
    out.append(block, sizeof block - stream.avail_out);
  }
  inflateEnd(&stream);
  if (status != Z_STREAM_END) return std::nullopt;
  return out;
}

std::string FirstDifference(const std::string& path, const std::string& a, const std::string& b) {
  if (EndsWith(path, ".pcap")) return PcapDifference(a, b);
  if (EndsWith(path, ".gz")) {
    const std::optional<std::string> text_a = Gunzip(a), text_b = Gunzip(b);
    if (text_a && text_b && *text_a != *text_b) {
      return "decompressed, " + TextDifference(*text_a, *text_b, EndsWith(path, ".csv.gz"));
    }
  }
  for (const char* text : {".csv", ".log", ".textproto", ".gnuplot", ".txt", ".json"}) {
    if (EndsWith(path, text)) return TextDifference(a, b, EndsWith(path, ".csv"));
  }
  const size_t at = Mismatch(a, b);
  return "first at byte " + std::to_string(at) + " (of " + std::to_string(a.size()) + " and " +
         std::to_string(b.size()) + ")";
}

}  // namespace sitlnet::verify
