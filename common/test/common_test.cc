#include "common/common.h"

#include <gtest/gtest.h>

namespace sitlnet {
namespace {

TEST(Ipv4Test, ParsesAndFormatsDottedQuads) {
  ASSERT_TRUE(ParseIpv4("10.77.0.1"));
  EXPECT_EQ(ParseIpv4("10.77.0.1")->host_order, 0x0a4d0001u);
  EXPECT_EQ(FormatIpv4(Ipv4{0xc0a80101u}), "192.168.1.1");
  EXPECT_FALSE(ParseIpv4("10.77.0"));
  EXPECT_FALSE(ParseIpv4("10.77.0.256"));
  EXPECT_FALSE(ParseIpv4("ten"));
}

TEST(Ipv4PrefixTest, RejectsHostBitsAndBadLengths) {
  EXPECT_TRUE(ParseIpv4Prefix("10.77.0.0/24"));
  EXPECT_FALSE(ParseIpv4Prefix("10.77.0.1/24"));
  EXPECT_FALSE(ParseIpv4Prefix("10.77.0.0/33"));
  EXPECT_FALSE(ParseIpv4Prefix("10.77.0.0"));
  EXPECT_FALSE(ParseIpv4Prefix("10.77.0.0/"));
}

TEST(Ipv4PrefixTest, OverlapIsSymmetricAndExact) {
  const auto a = *ParseIpv4Prefix("10.0.0.0/8");
  const auto b = *ParseIpv4Prefix("10.77.0.0/24");
  const auto c = *ParseIpv4Prefix("10.78.0.0/24");
  EXPECT_TRUE(a.Overlaps(b));
  EXPECT_TRUE(b.Overlaps(a));
  EXPECT_FALSE(b.Overlaps(c));
  EXPECT_TRUE(b.Contains(*ParseIpv4("10.77.0.254")));
  EXPECT_FALSE(b.Contains(*ParseIpv4("10.78.0.1")));
  EXPECT_EQ(FormatIpv4(b.Broadcast()), "10.77.0.255");
}

TEST(MacTest, RobotMacEncodesIndex) {
  EXPECT_EQ(FormatMac(RobotMac(0)), "02:00:00:00:00:00");
  EXPECT_EQ(FormatMac(RobotMac(258)), "02:00:00:00:01:02");
  EXPECT_FALSE(RobotMac(3).IsGroup());
}

}  // namespace
}  // namespace sitlnet

#include <fstream>
#include <sstream>

namespace sitlnet {
namespace {

TEST(LineFileTest, WritesHeaderAndWholeLinesOnFlush) {
  const std::string path = ::testing::TempDir() + "/line_file_test.csv";
  std::string text;
  auto read = [&] {
    std::ifstream file(path);
    std::ostringstream all;
    all << file.rdbuf();
    return all.str();
  };
  {
    LineFile file(path, "a,b", 2);
    EXPECT_EQ(read(), "a,b\n");
    file.Append("1,2");
    EXPECT_EQ(read(), "a,b\n");  // buffered until 2 lines
    file.Append("3,4");
    EXPECT_EQ(read(), "a,b\n1,2\n3,4\n");
    file.Append("5,6");
  }
  EXPECT_EQ(read(), "a,b\n1,2\n3,4\n5,6\n");
  EXPECT_THROW(LineFile("/nonexistent/dir/x.csv", ""), Error);
}

}  // namespace
}  // namespace sitlnet
