// Where `sitlnet view` may listen: loopback by default, another address only when allowed.
#include "view/listen_address.h"

#include <gtest/gtest.h>

namespace sitlnet::view {
namespace {

std::string Refusal(const std::string& text, bool allow_remote) {
  try {
    ParseListenAddress(text, allow_remote);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(ListenAddressTest, LoopbackAddressesParse) {
  const ListenAddress v4 = ParseListenAddress(kDefaultListen, false);
  EXPECT_EQ(v4.host, "127.0.0.1");
  EXPECT_EQ(v4.port, 7300);
  EXPECT_EQ(PageUrl(v4), "http://127.0.0.1:7300/");
  const ListenAddress v6 = ParseListenAddress("[::1]:0", false);
  EXPECT_EQ(v6.host, "::1");
  EXPECT_EQ(v6.port, 0);
  EXPECT_EQ(PageUrl(v6), "http://[::1]:0/");
  EXPECT_TRUE(IsLoopback("127.8.9.10"));
  EXPECT_FALSE(IsLoopback("128.0.0.1"));
}

TEST(ListenAddressTest, AnotherAddressNeedsTheFlag) {
  EXPECT_NE(Refusal("0.0.0.0:7300", false).find("--allow-remote"), std::string::npos);
  EXPECT_NE(Refusal("[::]:7300", false).find("not a loopback address"), std::string::npos);
  EXPECT_EQ(ParseListenAddress("0.0.0.0:7300", true).host, "0.0.0.0");
}

TEST(ListenAddressTest, BadTextIsNamed) {
  EXPECT_EQ(Refusal("127.0.0.1", false), "listen address \"127.0.0.1\": not ADDR:PORT");
  EXPECT_NE(Refusal("127.0.0.1:65536", false).find("port \"65536\" is not 0-65535"),
            std::string::npos);
  EXPECT_NE(Refusal("127.0.0.1:x", false).find("port \"x\""), std::string::npos);
  EXPECT_NE(Refusal("localhost:80", false).find("\"localhost\" is not a numeric"),
            std::string::npos);
}

}  // namespace
}  // namespace sitlnet::view
