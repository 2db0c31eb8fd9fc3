#include "coordinator/transport.h"

#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <thread>
#include <vector>

namespace sitlnet::coordinator {
namespace {

using proto::coord::CoordinatorMessage;

CoordinatorMessage StartMessage(uint64_t iteration, int robots) {
  CoordinatorMessage message;
  proto::coord::Start* start = message.mutable_start();
  start->set_iteration(iteration);
  start->set_start_ns(iteration * 10 * kNsPerMs);
  start->set_end_ns((iteration + 1) * 10 * kNsPerMs);
  for (int i = 0; i < 3 * robots; ++i) start->mutable_poses()->add_position_m(0.25 * i);
  return message;
}

std::string TempSocketPath(const char* name) {
  return "/tmp/sitlnet-coord-test-" + std::to_string(getpid()) + "-" + name + ".sock";
}

TEST(Endpoint, ParsesUnixAndTcpForms) {
  EXPECT_EQ(ParseEndpoint("unix:/run/x.sock").path, "/run/x.sock");
  EXPECT_EQ(ParseEndpoint("/run/x.sock").kind, Endpoint::Kind::kUnix);
  const Endpoint tcp = ParseEndpoint("10.0.0.2:7100");
  EXPECT_EQ(tcp.kind, Endpoint::Kind::kTcp);
  EXPECT_EQ(tcp.host, "10.0.0.2");
  EXPECT_EQ(tcp.port, 7100);
  EXPECT_EQ(ParseEndpoint("tcp:[::1]:9").host, "::1");
  try {
    ParseEndpoint("hostonly");
    FAIL();
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(),
                 "endpoint \"hostonly\": expected unix:/path, /path or host:port with port "
                 "0..65535");
  }
  EXPECT_THROW(ParseEndpoint("h:70000"), Error);
}

TEST(Channel, SocketPairCarriesManyFramesInOrder) {
  auto [a, b] = SocketPair();
  Channel left(std::move(a));
  Channel right(std::move(b));
  // More than the socket buffer holds, so sends must wait for the reader.
  std::thread writer([&] {
    for (uint64_t k = 0; k < 300; ++k) left.Send(StartMessage(k, 64));
  });
  CoordinatorMessage got;
  for (uint64_t k = 0; k < 300; ++k) {
    ASSERT_TRUE(right.Receive(&got, MonotonicNowNs() + 10 * kNsPerS));
    ASSERT_EQ(got.start().iteration(), k);
    ASSERT_EQ(got.start().poses().position_m_size(), 192);
  }
  writer.join();
}

TEST(Channel, CompressedFramesCrossTheSocket) {
  auto [a, b] = SocketPair();
  FrameCodecOptions options;
  options.compress_above_bytes = 100;
  Channel left(std::move(a), options);
  Channel right(std::move(b));  // Receivers accept both encodings whatever their own threshold.
  const CoordinatorMessage sent = StartMessage(7, 200);
  left.Send(sent);
  EXPECT_EQ(left.compressed_frames_sent(), 1u);
  CoordinatorMessage got;
  ASSERT_TRUE(right.Receive(&got, MonotonicNowNs() + kNsPerS));
  EXPECT_EQ(got.SerializeAsString(), sent.SerializeAsString());
}

TEST(Channel, TimeoutIsReportedAsTimeout) {
  auto [a, b] = SocketPair();
  Channel right(std::move(b));
  CoordinatorMessage got;
  try {
    right.Receive(&got, MonotonicNowNs() + 20 * kNsPerMs);
    FAIL();
  } catch (const TransportError& e) {
    EXPECT_EQ(e.kind(), TransportError::Kind::kTimeout);
    EXPECT_STREQ(e.what(), "timed out waiting for a frame");
  }
}

TEST(Channel, PeerCloseIsReportedAsClosed) {
  auto [a, b] = SocketPair();
  Channel right(std::move(b));
  a.Reset();
  CoordinatorMessage got;
  try {
    right.Receive(&got, MonotonicNowNs() + kNsPerS);
    FAIL();
  } catch (const TransportError& e) {
    EXPECT_EQ(e.kind(), TransportError::Kind::kClosed);
  }
}

TEST(Channel, CloseInTheMiddleOfAFrameIsReported) {
  auto [a, b] = SocketPair();
  Channel right(std::move(b));
  const uint8_t partial[10] = {100, 0, 0, 0, 0, 0, 0, 0, 1, 2};  // Announces 100 bytes, sends 2.
  ASSERT_EQ(write(a.get(), partial, sizeof partial), 10);
  a.Reset();
  CoordinatorMessage got;
  try {
    right.Receive(&got, MonotonicNowNs() + kNsPerS);
    FAIL();
  } catch (const TransportError& e) {
    EXPECT_EQ(e.kind(), TransportError::Kind::kClosed);
    EXPECT_STREQ(e.what(), "peer closed the connection in the middle of a frame");
  }
}

TEST(Channel, OversizedFrameIsRejectedWithoutReadingIt) {
  auto [a, b] = SocketPair();
  FrameCodecOptions small;
  small.max_frame_bytes = 1000;
  Channel right(std::move(b), small);
  const uint8_t header[8] = {0xe9, 0x03, 0, 0, 0, 0, 0, 0};  // 1001 bytes.
  ASSERT_EQ(write(a.get(), header, sizeof header), 8);
  CoordinatorMessage got;
  try {
    right.Receive(&got, MonotonicNowNs() + kNsPerS);
    FAIL();
  } catch (const TransportError& e) {
    EXPECT_EQ(e.kind(), TransportError::Kind::kBadFrame);
    EXPECT_STREQ(e.what(), "bad frame: body of 1001 bytes exceeds the limit of 1000 bytes");
  }
}

TEST(Channel, InterruptFdEndsAWaitWithoutConsumingAnything) {
  auto [a, b] = SocketPair();
  auto [wake_write, wake_read] = SocketPair();
  Channel right(std::move(b));
  ASSERT_EQ(write(wake_write.get(), "x", 1), 1);
  CoordinatorMessage got;
  EXPECT_FALSE(right.Receive(&got, kNoDeadline, wake_read.get()));
}

void ExchangeOver(const Endpoint& where) {
  Listener listener(where);
  std::thread client([endpoint = listener.endpoint()] {
    Channel channel(Connect(endpoint, MonotonicNowNs() + 5 * kNsPerS));
    channel.Send(StartMessage(1, 8));
    CoordinatorMessage reply;
    ASSERT_TRUE(channel.Receive(&reply, MonotonicNowNs() + 5 * kNsPerS));
    EXPECT_EQ(reply.end().iteration(), 1u);
  });
  Channel server(listener.Accept(MonotonicNowNs() + 5 * kNsPerS));
  CoordinatorMessage got;
  ASSERT_TRUE(server.Receive(&got, MonotonicNowNs() + 5 * kNsPerS));
  EXPECT_EQ(got.start().poses().position_m_size(), 24);
  CoordinatorMessage reply;
  reply.mutable_end()->set_iteration(1);
  server.Send(reply);
  client.join();
}

TEST(Listener, UnixSocketRoundTrip) {
  const std::string path = TempSocketPath("uds");
  ExchangeOver(ParseEndpoint("unix:" + path));
  EXPECT_NE(access(path.c_str(), F_OK), 0) << "socket file left behind";
}

TEST(Listener, UnixSocketIsOwnerOnlyWhateverTheUmask) {
  const std::string path = TempSocketPath("mode");
  const mode_t old_umask = umask(0);
  {
    Listener listener(ParseEndpoint("unix:" + path));
    umask(old_umask);
    struct stat st {};
    ASSERT_EQ(stat(path.c_str(), &st), 0);
    EXPECT_EQ(st.st_mode & 0777, 0600u);
  }
  umask(old_umask);
  unlink(path.c_str());
}

TEST(Listener, TcpLoopbackRoundTripOnAnEphemeralPort) {
  ExchangeOver(ParseEndpoint("127.0.0.1:0"));
}

TEST(Listener, AcceptTimesOut) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  EXPECT_THROW(listener.Accept(MonotonicNowNs() + 10 * kNsPerMs), TransportError);
}

TEST(Connect, NamesTheEndpointWhenNobodyListens) {
  const std::string path = TempSocketPath("nobody");
  try {
    Connect(ParseEndpoint(path), MonotonicNowNs());
    FAIL();
  } catch (const TransportError& e) {
    EXPECT_EQ(std::string(e.what()), "connect to unix:" + path + ": No such file or directory");
  }
}

// A peer that never answers the SYN (a host that is down or filtered) costs
// the deadline, not the kernel's ~2 minutes of SYN retries. On loopback: a
// listener with a full accept queue drops SYNs (tcp_abort_on_overflow = 0).
TEST(Connect, GivesUpAtTheDeadlineWhenTheSynIsNeverAnswered) {
  const int listener = socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(listener, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  ASSERT_EQ(listen(listener, 0), 0);  // Room for one connection, never accepted.
  socklen_t length = sizeof address;
  getsockname(listener, reinterpret_cast<sockaddr*>(&address), &length);
  std::vector<int> fillers;
  for (int i = 0; i < 2; ++i) {
    fillers.push_back(socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0));
    connect(fillers.back(), reinterpret_cast<sockaddr*>(&address), sizeof address);
  }
  const TimeNs begin = MonotonicNowNs();
  try {
    Connect(ParseEndpoint("127.0.0.1:" + std::to_string(ntohs(address.sin_port))),
            begin + 300 * kNsPerMs);
    FAIL() << "connected to a full accept queue";
  } catch (const TransportError& e) {
    EXPECT_EQ(e.kind(), TransportError::Kind::kTimeout) << e.what();
    EXPECT_NE(std::string(e.what()).find("no answer before the deadline"), std::string::npos)
        << e.what();
  }
  const TimeNs waited = MonotonicNowNs() - begin;
  EXPECT_GE(waited, 300 * kNsPerMs);
  EXPECT_LT(waited, 900 * kNsPerMs);  // The first SYN retry is due at 1 s.
  for (int fd : fillers) close(fd);
  close(listener);
}

}  // namespace
}  // namespace sitlnet::coordinator
