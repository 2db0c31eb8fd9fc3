// The shared-secret handshake (docs/coordinator.md, "Authentication"), attacked: a connector
// without the secret, with another secret, a hand-made client that sends a made-up proof, and a
// coordinator that cannot prove the secret are all refused, and the connectors that hold it are
// accepted after them; secret files that others can read, links and short secrets are refused.
#include "coordinator/authentication.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
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
    proto::coord::CoordinatorMessage hello;
    hello.mutable_hello()->set_protocol_version(kProtocolVersion);
    hello.mutable_hello()->set_scenario_hash(kHash);
    hello.mutable_hello()->set_role(proto::coord::ROLE_PHYSICS);
    hello.mutable_hello()->set_connector_name("forger");
    hello.mutable_hello()->set_nonce(RandomNonce());
    client.Send(hello);
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
  std::string hex;
  for (unsigned char c : expected) {
    char two[3];
    std::snprintf(two, sizeof two, "%02x", c);
    hex += two;
  }
  EXPECT_EQ(hex, "7fecfee5e026c626dbc9102e479124012035da516105c95ca00301e37d7c4321");
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
