// Sha256HexOfFile against two oracles: the FIPS 180-2 example digests, and coreutils'
// sha256sum on a file larger than the 1 MiB read block.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <random>
#include <string>

#include "common/common.h"

namespace sitlnet {
namespace {

std::string WriteFile(const std::string& name, const std::string& bytes) {
  const std::string path = ::testing::TempDir() + "/" + name + std::to_string(getpid());
  std::ofstream(path, std::ios::binary) << bytes;
  return path;
}

// What `sha256sum PATH` prints before its two spaces.
std::string Sha256sum(const std::string& path) {
  FILE* pipe = popen(("sha256sum '" + path + "'").c_str(), "r");
  if (pipe == nullptr) return "";
  char digest[65] = {};
  const size_t n = fread(digest, 1, 64, pipe);
  pclose(pipe);
  return std::string(digest, n);
}

TEST(Sha256Test, MatchesTheStandardsExamples) {
  // FIPS 180-2, appendix B.1 ("abc") and the digest of the empty message.
  EXPECT_EQ(Sha256HexOfFile(WriteFile("abc", "abc")),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  EXPECT_EQ(Sha256HexOfFile(WriteFile("empty", "")),
            "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
}

TEST(Sha256Test, MatchesSha256sumAcrossReadBlocks) {
  std::mt19937 bytes(7);  // Seeded: the same file every time.
  std::string content(3 * (1 << 20) + 12345, '\0');
  for (char& c : content) c = static_cast<char>(bytes());
  const std::string path = WriteFile("blocks", content);
  const std::string expected = Sha256sum(path);
  ASSERT_EQ(expected.size(), 64u) << "sha256sum (coreutils) did not run";
  EXPECT_EQ(Sha256HexOfFile(path), expected);
}

TEST(Sha256Test, AMissingFileIsNamed) {
  try {
    Sha256HexOfFile("/nonexistent/run/trajectories.csv");
    FAIL() << "no error";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/run/trajectories.csv"),
              std::string::npos)
        << error.what();
  }
}

TEST(VersionTest, IsACommitOrUnknown) {
  const std::string version(SitlnetVersion());
  if (version == "unknown") return;
  ASSERT_EQ(version.size(), 40u) << version;
  EXPECT_EQ(version.find_first_not_of("0123456789abcdef"), std::string::npos) << version;
}

}  // namespace
}  // namespace sitlnet
