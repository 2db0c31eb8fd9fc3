// The --gcs forms, accepted and refused.
#include <gtest/gtest.h>

#include "gcs_link/gcs_link.h"

namespace sitlnet::gcs {
namespace {

TEST(GcsEndpointTest, UdpAndTcpListenAreParsed) {
  const GcsEndpoint udp = ParseGcsEndpoint("udp:192.168.1.20:14551");
  EXPECT_EQ(udp.kind, GcsEndpoint::Kind::kUdp);
  EXPECT_EQ(udp.host, "192.168.1.20");
  EXPECT_EQ(udp.port, 14551);
  const GcsEndpoint tcp = ParseGcsEndpoint("tcp-listen:5760");
  EXPECT_EQ(tcp.kind, GcsEndpoint::Kind::kTcpListen);
  EXPECT_EQ(tcp.port, 5760);
  const GcsEndpoint fallback = DefaultGcsEndpoint();
  EXPECT_EQ(fallback.text, "udp:127.0.0.1:14550");
}

TEST(GcsEndpointTest, OtherFormsAreRefusedNamingTheText) {
  for (const char* text :
       {"", "udp:", "udp:127.0.0.1", "udp:localhost:14550", "udp:1.2.3.4:0", "udp:1.2.3.4:65536",
        "udp:1.2.3.4:-1", "tcp-listen:", "tcp-listen:x", "tcp:1.2.3.4:5760", "14550"}) {
    try {
      ParseGcsEndpoint(text);
      ADD_FAILURE() << "accepted '" << text << "'";
    } catch (const Error& error) {
      EXPECT_EQ(std::string(error.what()).rfind(std::string("--gcs ") + text + ":", 0), 0u)
          << error.what();
    }
  }
}

}  // namespace
}  // namespace sitlnet::gcs
