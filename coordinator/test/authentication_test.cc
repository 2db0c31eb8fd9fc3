// The shared-secret handshake (docs/coordinator.md, "Authentication"), attacked: a connector
// without the secret, with another secret, a hand-made client that sends a made-up proof, and a
// coordinator that cannot prove the secret are all refused, and the connectors that hold it are
// accepted after them; secret files that others can read, links and short secrets are refused.
// The messages after it, attacked by a relay on the path that lets the handshake through and then
// injects or rewrites: each end refuses the first message that is not the other end's.
#include "coordinator/authentication.h"

#include <gtest/gtest.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <functional>
#include <future>

#include "coordinator/coordinator.h"
#include "coordinator/test/test_connectors.h"

namespace sitlnet::coordinator {
namespace {

using namespace test_support;  // NOLINT: test helpers.

const std::string kSecret = "0123456789abcdef0123456789abcdef";

HandshakeExpectation ExpectSecret() {
  HandshakeExpectation expect = Expect();
  expect.secret = kSecret;
  return expect;
}

std::string HexOf(const std::string& bytes) {
  std::string hex;
  for (unsigned char c : bytes) {
    char two[3];
    std::snprintf(two, sizeof two, "%02x", c);
    hex += two;
  }
  return hex;
}

// A physics connector's Hello with a fresh nonce, as a hand-made client sends it.
proto::coord::CoordinatorMessage HelloWithNonce(const std::string& name) {
  proto::coord::CoordinatorMessage hello;
  hello.mutable_hello()->set_protocol_version(kProtocolVersion);
  hello.mutable_hello()->set_scenario_hash(kHash);
  hello.mutable_hello()->set_role(proto::coord::ROLE_PHYSICS);
  hello.mutable_hello()->set_connector_name(name);
  hello.mutable_hello()->set_nonce(RandomNonce());
  return hello;
}

// Ends a run of two accepted connectors: both get Stop, and both served without an error.
void StopAndExpectBothServedCleanly(AcceptedConnectors& accepted, ConnectorThread& phys,
                                    ConnectorThread& net) {
  accepted.physics->Stop("done");
  accepted.network->Stop("done");
  phys.Join();
  net.Join();
  EXPECT_EQ(phys.error(), "");
  EXPECT_EQ(net.error(), "");
}

// Bytes of one encoded message.
std::string FrameOf(const proto::coord::CoordinatorMessage& message) {
  FrameEncoder encoder;
  return std::string(encoder.Encode(message));
}

// An attacker on the path: it accepts the connector's connection, opens its own to the
// coordinator, and passes every frame on through `edit` (direction, index of the frame in that
// direction, its bytes with its tag if it has one), which returns what to send instead. It knows
// the framing and where the tags start (after the coordinator's Challenge and the connector's
// Proof), not the secret.
class OnPathRelay {
 public:
  enum Direction { kToConnector, kToCoordinator };
  using Edit = std::function<std::string(Direction, int, const std::string&)>;

  OnPathRelay(Listener& front, const Endpoint& coordinator, Edit edit)
      : thread_([&front, coordinator, edit] {
          try {
            UniqueFd connector = front.Accept(MonotonicNowNs() + 10 * kNsPerS);
            UniqueFd upstream = Connect(coordinator, MonotonicNowNs() + 5 * kNsPerS);
            Pass(connector, upstream, edit);
          } catch (const Error&) {
            // Either end gone: the relay's work is over.
          }
        }) {}
  ~OnPathRelay() { thread_.join(); }

 private:
  static void Pass(UniqueFd& connector, UniqueFd& upstream, const Edit& edit) {
    // Per direction: bytes not yet passed on, frames passed on, first tagged frame.
    struct Side {
      int from;
      int to;
      Direction direction;
      int tagged_from;
      std::string pending;
      int frames = 0;
    };
    Side sides[2] = {{upstream.get(), connector.get(), kToConnector, 1, {}},
                     {connector.get(), upstream.get(), kToCoordinator, 2, {}}};
    for (;;) {
      pollfd fds[2] = {{sides[0].from, POLLIN, 0}, {sides[1].from, POLLIN, 0}};
      if (poll(fds, 2, 10000) <= 0) return;
      for (int i = 0; i < 2; ++i) {
        if (fds[i].revents == 0) continue;
        Side& side = sides[i];
        char buffer[65536];
        const ssize_t n = recv(side.from, buffer, sizeof buffer, 0);
        if (n <= 0) return;
        side.pending.append(buffer, static_cast<size_t>(n));
        for (;;) {
          if (side.pending.size() < kFrameHeaderBytes) break;
          uint32_t body = 0;
          std::memcpy(&body, side.pending.data(), 4);  // Little-endian, like this machine.
          const size_t size =
              kFrameHeaderBytes + body + (side.frames >= side.tagged_from ? kMessageTagBytes : 0);
          if (side.pending.size() < size) break;
          const std::string out = edit(side.direction, side.frames++, side.pending.substr(0, size));
          side.pending.erase(0, size);
          if (send(side.to, out.data(), out.size(), MSG_NOSIGNAL) !=
              static_cast<ssize_t>(out.size())) {
            return;
          }
        }
      }
    }
  }

  std::thread thread_;
};

TEST(Authentication, OnlyConnectorsThatProveTheSecretAreAccepted) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  auto accepting = std::async(std::launch::async, [&] {
    return AcceptConnectors(listener, ExpectSecret(), Within(20 * kNsPerS));
  });
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  {
    ConnectorThread plain(listener.endpoint(), &network_sim, {"plain", Role::kNetwork, kHash, {}});
    plain.Join();
    EXPECT_EQ(plain.error(),
              "the coordinator refused: network connector 'plain' did not authenticate: this "
              "coordinator needs the shared secret (--secret-file on both ends)");
  }
  {
    // Another secret: the coordinator's proof does not check out, and the connector stops
    // before it proves anything itself.
    ConnectorThread other(listener.endpoint(), &physics_sim,
                          {"other", Role::kPhysics, kHash, "another secret, 16+ bytes"});
    other.Join();
    EXPECT_EQ(other.error(),
              "the coordinator failed to prove the shared secret (a different --secret-file, or "
              "not sitlnet's coordinator)");
  }
  {
    // An attacker who skips the check and answers with a made-up proof.
    Channel client(Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS));
    client.Send(HelloWithNonce("forger"));
    proto::coord::CoordinatorMessage in;
    ASSERT_TRUE(client.Receive(&in, MonotonicNowNs() + 5 * kNsPerS));
    ASSERT_TRUE(in.has_challenge());
    EXPECT_EQ(in.challenge().nonce().size(), kNonceBytes);
    proto::coord::CoordinatorMessage proof;
    proof.mutable_proof()->set_proof(std::string(32, 'x'));
    client.Send(proof);
    ASSERT_TRUE(client.Receive(&in, MonotonicNowNs() + 5 * kNsPerS));
    ASSERT_TRUE(in.has_error());
    EXPECT_EQ(in.error().message(),
              "physics connector 'forger' failed to prove the shared secret (a different "
              "--secret-file?)");
  }
  ConnectorThread phys(listener.endpoint(), &physics_sim,
                       {"phys0", Role::kPhysics, kHash, kSecret});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, kSecret});
  AcceptedConnectors c = accepting.get();
  ASSERT_TRUE(c.physics && c.network);
  EXPECT_EQ(RunCoordinator(*c.physics, *c.network, Lockstep(5)).iterations_done, 5);
  phys.Join();
  net.Join();
  EXPECT_EQ(phys.error(), "");
  EXPECT_EQ(net.error(), "");
}

TEST(Authentication, AConnectorWithASecretRefusesACoordinatorWithout) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim,
                       {"phys0", Role::kPhysics, kHash, kSecret});
  EXPECT_THROW(AcceptConnector(Channel(listener.Accept(MonotonicNowNs() + 5 * kNsPerS)), Expect(),
                               Within(5 * kNsPerS)),
               StrayConnectionError);
  phys.Join();
  EXPECT_EQ(phys.error(),
            "the coordinator refused: physics connector 'phys0' wants to authenticate with a "
            "shared secret, but this coordinator has none (--secret-file)");
}

TEST(Authentication, ProofsDependOnTheSecretTheNoncesAndTheDirection) {
  const std::string a = RandomNonce(), b = RandomNonce();
  EXPECT_NE(a, b);
  const std::string proof = ProofOf(kSecret, "sitlnet coordinator", a, b);
  EXPECT_EQ(proof.size(), 32u);
  EXPECT_TRUE(SameProof(proof, ProofOf(kSecret, "sitlnet coordinator", a, b)));
  EXPECT_FALSE(SameProof(proof, ProofOf(kSecret + "x", "sitlnet coordinator", a, b)));
  EXPECT_FALSE(SameProof(proof, ProofOf(kSecret, "sitlnet connector", a, b)));
  EXPECT_FALSE(SameProof(proof, ProofOf(kSecret, "sitlnet coordinator", b, a)));
  // The message is label, NUL, first, second: HMAC-SHA256 as Python's hmac module computes it
  // (hmac.new(b"Jefe", b"sitlnet coordinator\x00" + b"A" * 32 + b"B" * 32, hashlib.sha256)).
  const std::string expected =
      ProofOf("Jefe", "sitlnet coordinator", std::string(32, 'A'), std::string(32, 'B'));
  EXPECT_EQ(HexOf(expected), "7fecfee5e026c626dbc9102e479124012035da516105c95ca00301e37d7c4321");
}

TEST(Authentication, MessageTagsAreHmacSha256OfTheSequenceNumberAndTheFrame) {
  // As Python's hmac module computes them: hmac.new(b"Jefe", struct.pack("<Q", n) + frame,
  // hashlib.sha256) for n = 0 and 1.
  MessageTagger tagger("Jefe");
  const std::string frame = "what do ya want for nothing?";
  std::string tag(kMessageTagBytes, '\0');
  tagger.TagNext(frame, reinterpret_cast<unsigned char*>(tag.data()));
  EXPECT_EQ(HexOf(tag), "d524ab401192a2b9f214a6a4feff4277ba99d7c4abd37f5caa3f2508a541cd22");
  tagger.TagNext(frame, reinterpret_cast<unsigned char*>(tag.data()));
  EXPECT_EQ(HexOf(tag), "af9265e8ba557f118a00af6e3530f325c1cb82b6e3927aae35d37b6b101efd57");
  EXPECT_EQ(tagger.count(), 2u);
  const SessionKeys keys = DeriveSessionKeys(kSecret, std::string(32, 'A'), std::string(32, 'B'));
  EXPECT_NE(keys.coordinator_to_connector, keys.connector_to_coordinator);
  EXPECT_NE(keys.coordinator_to_connector,
            DeriveSessionKeys(kSecret, std::string(32, 'B'), std::string(32, 'A'))
                .coordinator_to_connector);
}

TEST(Authentication, ATaggedChannelRefusesARepeatedAnUntaggedAndAReflectedFrame) {
  auto [sender_fd, wire_in] = SocketPair();
  auto [wire_out, receiver_fd] = SocketPair();
  Channel sender(std::move(sender_fd));
  Channel receiver(std::move(receiver_fd));
  sender.AuthenticateMessages("key one, sixteen+", "key two, sixteen+");
  receiver.AuthenticateMessages("key two, sixteen+", "key one, sixteen+");
  proto::coord::CoordinatorMessage message;
  message.mutable_start()->set_iteration(7);
  sender.Send(message);
  std::string sent(FrameOf(message).size() + kMessageTagBytes, '\0');
  ASSERT_EQ(recv(wire_in.get(), sent.data(), sent.size(), MSG_WAITALL),
            static_cast<ssize_t>(sent.size()));
  auto deliver = [&](const std::string& bytes) {
    ASSERT_EQ(send(wire_out.get(), bytes.data(), bytes.size(), 0),
              static_cast<ssize_t>(bytes.size()));
  };
  auto refusal = [](Channel& channel) -> std::string {
    proto::coord::CoordinatorMessage in;
    try {
      channel.Receive(&in, MonotonicNowNs() + 5 * kNsPerS);
    } catch (const TransportError& e) {
      return std::string(e.kind() == TransportError::Kind::kBadFrame ? "" : "not a bad frame: ") +
             e.what();
    }
    return "accepted iteration " + std::to_string(in.start().iteration());
  };
  const std::string kFailed =
      " of the connection failed authentication (changed, added, dropped or repeated on the way)";
  deliver(sent);
  EXPECT_EQ(refusal(receiver), "accepted iteration 7");
  // Counted as they crossed the socket, frame and tag, the same at both ends.
  EXPECT_EQ(sender.bytes_sent(), sent.size());
  EXPECT_EQ(receiver.bytes_received(), sent.size());
  deliver(sent);  // The same frame again: its sequence number is now 1.
  EXPECT_EQ(refusal(receiver), "message 1" + kFailed);
  EXPECT_EQ(receiver.bytes_received(), sent.size());  // A refused frame is no message.
  // A frame without a tag: what follows it (a longer message) is read as its tag.
  auto [plain_fd, plain_receiver_fd] = SocketPair();
  Channel plain_receiver(std::move(plain_receiver_fd));
  plain_receiver.AuthenticateMessages("key two, sixteen+", "key one, sixteen+");
  proto::coord::CoordinatorMessage stop;
  stop.mutable_stop()->set_reason(std::string(64, 'r'));
  const std::string plain = FrameOf(message) + FrameOf(stop);
  ASSERT_EQ(send(plain_fd.get(), plain.data(), plain.size(), 0),
            static_cast<ssize_t>(plain.size()));
  EXPECT_EQ(refusal(plain_receiver), "message 0" + kFailed);
  // The sender's own first message sent back to it: the other direction's key.
  auto [reflect_fd, reflect_receiver_fd] = SocketPair();
  Channel reflected(std::move(reflect_receiver_fd));
  reflected.AuthenticateMessages("key one, sixteen+", "key two, sixteen+");
  ASSERT_EQ(send(reflect_fd.get(), sent.data(), sent.size(), 0), static_cast<ssize_t>(sent.size()));
  EXPECT_EQ(refusal(reflected), "message 0" + kFailed);
}

// Fails without the tags: the injected Stop ends the connector "orderly" with the attacker's
// reason, and the forged End reaches the coordinator as the physics' poses.
TEST(Authentication, ARelayOnThePathCannotInjectOrRewriteMessagesAfterTheHandshake) {
  Listener coordinator_listener(ParseEndpoint("127.0.0.1:0"));
  {
    // Towards the connector: a Stop injected right after the Welcome.
    Listener front(ParseEndpoint("127.0.0.1:0"));
    OnPathRelay relay(front, coordinator_listener.endpoint(),
                      [](OnPathRelay::Direction direction, int index, const std::string& frame) {
                        if (direction != OnPathRelay::kToConnector || index != 1) return frame;
                        proto::coord::CoordinatorMessage stop;
                        stop.mutable_stop()->set_reason("the attacker's");
                        return frame + FrameOf(stop) + std::string(kMessageTagBytes, 'x');
                      });
    auto accepting = std::async(std::launch::async, [&] {
      return AcceptConnectorOfRole(coordinator_listener, Role::kPhysics, ExpectSecret(),
                                   Within(10 * kNsPerS));
    });
    SyntheticPhysics physics_sim(Robots(1));
    ConnectorThread phys(front.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, kSecret});
    phys.Join();
    EXPECT_EQ(phys.stop_reason(), "");
    EXPECT_EQ(phys.error(),
              "coordinator connection: message 1 of the connection failed authentication "
              "(changed, added, dropped or repeated on the way)");
    accepting.get()->Stop("done");
  }
  {
    // Towards the coordinator: the physics' first answer replaced by a made-up End.
    Listener front(ParseEndpoint("127.0.0.1:0"));
    OnPathRelay relay(front, coordinator_listener.endpoint(),
                      [](OnPathRelay::Direction direction, int index, const std::string& frame) {
                        if (direction != OnPathRelay::kToCoordinator || index != 2) return frame;
                        proto::coord::CoordinatorMessage end;
                        end.mutable_end()->set_iteration(0);
                        return FrameOf(end) + frame.substr(frame.size() - kMessageTagBytes);
                      });
    auto accepting = std::async(std::launch::async, [&] {
      return AcceptConnectorOfRole(coordinator_listener, Role::kPhysics, ExpectSecret(),
                                   Within(10 * kNsPerS));
    });
    SyntheticPhysics physics_sim(Robots(1));
    ConnectorThread phys(front.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, kSecret});
    std::unique_ptr<Connector> connector = accepting.get();
    ASSERT_NE(connector, nullptr);
    proto::coord::Start start;
    start.set_iteration(0);
    start.set_end_ns(kDelta);
    connector->Begin(start, Within(5 * kNsPerS));
    proto::coord::End end;
    try {
      connector->Finish(0, &end, Within(5 * kNsPerS));
      ADD_FAILURE() << "the forged End was taken";
    } catch (const Error& e) {
      EXPECT_EQ(std::string(e.what()),
                "physics connector 'phys0' failed during iteration 0: message 0 of the connection "
                "failed authentication (changed, added, dropped or repeated on the way)");
    }
    connector->Stop("done");
    connector.reset();
    phys.Join();
  }
}

// Fails with handshakes one at a time: each of the two strangers holds the accept loop for its
// Hello deadline (2 s) and is then ignored with a warning, before the real connectors are looked
// at.
TEST(Authentication, AConnectionThatSaysNothingOrStopsHalfWayHoldsBackNoConnector) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  ::testing::internal::CaptureStderr();
  auto accepting = std::async(std::launch::async, [&] {
    return AcceptConnectors(listener, ExpectSecret(), Within(20 * kNsPerS));
  });
  UniqueFd silent = Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS);
  // A stranger that starts the handshake and never proves anything.
  Channel half_way(Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS));
  half_way.Send(HelloWithNonce("half-way"));
  proto::coord::CoordinatorMessage in;
  ASSERT_TRUE(half_way.Receive(&in, MonotonicNowNs() + 5 * kNsPerS));
  ASSERT_TRUE(in.has_challenge());
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim,
                       {"phys0", Role::kPhysics, kHash, kSecret});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, kSecret});
  AcceptedConnectors accepted = accepting.get();
  const std::string warnings = ::testing::internal::GetCapturedStderr();
  ASSERT_NE(accepted.physics, nullptr);
  ASSERT_NE(accepted.network, nullptr);
  EXPECT_EQ(accepted.physics->name(), "phys0");
  // Both strangers were still under way when the connectors were in: nothing was ignored yet.
  EXPECT_EQ(warnings, "");
  StopAndExpectBothServedCleanly(accepted, phys, net);
}

// Fails when the proofs cover only the nonces: the relay renames the connector (it could as well
// change its scenario hash or initial poses) and the coordinator accepts it.
TEST(Authentication, ARelayThatChangesTheHelloFailsBothProofs) {
  Listener coordinator_listener(ParseEndpoint("127.0.0.1:0"));
  Listener front(ParseEndpoint("127.0.0.1:0"));
  OnPathRelay relay(front, coordinator_listener.endpoint(),
                    [](OnPathRelay::Direction direction, int index, const std::string& frame) {
                      if (direction != OnPathRelay::kToCoordinator || index != 0) return frame;
                      proto::coord::CoordinatorMessage hello;
                      EXPECT_TRUE(hello.ParseFromString(frame.substr(kFrameHeaderBytes)));
                      hello.mutable_hello()->set_connector_name("renamed");
                      return FrameOf(hello);
                    });
  auto accepting = std::async(std::launch::async, [&] {
    return AcceptConnectorOfRole(coordinator_listener, Role::kPhysics, ExpectSecret(),
                                 Within(kNsPerS));
  });
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(front.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, kSecret});
  phys.Join();
  EXPECT_EQ(phys.error(),
            "the coordinator failed to prove the shared secret (a different --secret-file, or "
            "not sitlnet's coordinator)");
  EXPECT_THROW(accepting.get(), Error);  // Nothing accepted before the deadline.
}

// Fails when a connection beyond the 16 handshakes under way is closed at once: then a stranger
// holding 16 silent connections keeps the real connectors out. Now they wait in the backlog and
// are accepted as soon as a slot frees (the silent ones are dropped after 2 s).
TEST(Authentication, SixteenSilentConnectionsKeepNoConnectorOut) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  auto accepting = std::async(std::launch::async, [&] {
    return AcceptConnectors(listener, ExpectSecret(), Within(20 * kNsPerS));
  });
  std::vector<UniqueFd> silent;
  for (int i = 0; i < 16; ++i)
    silent.push_back(Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS));
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim,
                       {"phys0", Role::kPhysics, kHash, kSecret});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, kSecret});
  AcceptedConnectors accepted = accepting.get();
  ASSERT_NE(accepted.physics, nullptr);
  ASSERT_NE(accepted.network, nullptr);
  StopAndExpectBothServedCleanly(accepted, phys, net);
}

TEST(Authentication, SecretFilesMustBeTheUsersOwnAndPrivate) {
  const std::string dir = ::testing::TempDir() + "/sitlnet_secret_" + std::to_string(getpid());
  mkdir(dir.c_str(), 0700);
  const std::string path = dir + "/key";
  std::ofstream(path) << kSecret;
  chmod(path.c_str(), 0600);
  EXPECT_EQ(LoadSecretFile(path), kSecret);
  chmod(path.c_str(), 0640);
  try {
    LoadSecretFile(path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "secret file " + path +
                                         ": mode 0640 lets others read or write it (chmod 600 " +
                                         path + ")");
  }
  chmod(path.c_str(), 0600);
  const std::string link = dir + "/link";
  ASSERT_EQ(symlink(path.c_str(), link.c_str()), 0);
  EXPECT_THROW(LoadSecretFile(link), Error);  // O_NOFOLLOW
  const std::string short_path = dir + "/short";
  std::ofstream(short_path) << "short";
  chmod(short_path.c_str(), 0600);
  try {
    LoadSecretFile(short_path);
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()).rfind("secret file " + short_path +
                                              ": 5 bytes, expected 16 to "
                                              "4096",
                                          0),
              0u);
  }
  EXPECT_THROW(LoadSecretFile(dir + "/missing"), Error);
  std::remove(link.c_str());
  std::remove(path.c_str());
  std::remove(short_path.c_str());
  rmdir(dir.c_str());
}

}  // namespace
}  // namespace sitlnet::coordinator
