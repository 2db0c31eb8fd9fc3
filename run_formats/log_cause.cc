#include "run_formats/run_formats.h"

#include <algorithm>
#include <cctype>
#include <fstream>
#include <sstream>
#include <vector>

namespace sitlnet::run_formats {
namespace {

constexpr size_t kMaxLineChars = 200;

// Printable characters only (a log may hold colour codes or binary), trimmed, cut.
std::string Clean(const std::string& line) {
  std::string out;
  for (const char c : line) {
    if (std::isprint(static_cast<unsigned char>(c))) out += c;
  }
  const size_t first = out.find_first_not_of(' ');
  if (first == std::string::npos) return "";
  out = out.substr(first, out.find_last_not_of(' ') - first + 1);
  if (out.size() > kMaxLineChars) out = out.substr(0, kMaxLineChars - 3) + "...";
  return out;
}

bool ReadsLikeAnError(std::string line) {
  std::transform(line.begin(), line.end(), line.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static const std::vector<std::string> kWords = {
      "error", "panic", "fatal", "fail", "denied", "not found", "no such", "cannot",
      "unrecognized", "invalid"};
  return std::any_of(kWords.begin(), kWords.end(),
                     [&](const std::string& word) { return line.find(word) != std::string::npos; });
}

}  // namespace

std::string FirstErrorLine(const std::string& log) {
  std::istringstream lines(log);
  for (std::string line; std::getline(lines, line);) {
    const std::string clean = Clean(line);
    if (!clean.empty() && ReadsLikeAnError(clean)) return clean;
  }
  return LastLine(log);
}

std::string LastLine(const std::string& log) {
  std::istringstream lines(log);
  std::string last;
  for (std::string line; std::getline(lines, line);) {
    if (std::string clean = Clean(line); !clean.empty()) last = std::move(clean);
  }
  return last;
}

std::string ReadLogTail(const std::string& path, size_t max_bytes) {
  std::ifstream file(path, std::ios::binary | std::ios::ate);
  if (!file) return "";
  const std::streamoff size = file.tellg();
  const std::streamoff start = std::max<std::streamoff>(0, size - static_cast<std::streamoff>(max_bytes));
  file.seekg(start);
  std::string text(static_cast<size_t>(size - start), '\0');
  file.read(text.data(), static_cast<std::streamsize>(text.size()));
  text.resize(static_cast<size_t>(file.gcount()));
  // A cut first line is not a line of the log.
  if (start > 0) text.erase(0, text.find('\n') == std::string::npos ? 0 : text.find('\n') + 1);
  return text;
}

std::string LogSays(const std::string& line) {
  return line.empty() ? "" : "; its log says \"" + line + "\"";
}

}  // namespace sitlnet::run_formats
