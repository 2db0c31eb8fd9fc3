// Accepting connectors: the handshake's checks (scenario, protocol, role),
// stray connections, duplicates, and connectors that never come.
#include <gtest/gtest.h>
#include <unistd.h>

#include "coordinator/coordinator.h"
#include "coordinator/test/test_connectors.h"

namespace sitlnet::coordinator {
namespace {

using namespace test_support;  // NOLINT: test helpers.

TEST(Coordinator, HandshakeRefusesAnotherScenarioAndSaysSoToBothSides) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash + 1, {}});
  const std::string expected =
      "physics connector 'phys0' loaded a different scenario: hash 0x51170e7000000002, the "
      "coordinator's is 0x51170e7000000001";
  try {
    AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.what(), expected);
  }
  phys.Join();
  EXPECT_EQ(phys.error(), "the coordinator refused: " + expected);
}

TEST(Coordinator, StrayConnectionsAreIgnoredAndTheConnectorsStillAccepted) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  // Garbage first (a bad frame), then a client that closes at once.
  UniqueFd garbage = Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS);
  ASSERT_EQ(write(garbage.get(), "GET / HTTP/1.0\r\n\r\n", 18), 18);
  UniqueFd closer = Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS);
  closer.Reset();
  SyntheticPhysics physics_sim(Robots(1));
  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
  AcceptedConnectors c = AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
  ASSERT_TRUE(c.physics && c.network);
  EXPECT_EQ(RunCoordinator(*c.physics, *c.network, Lockstep(5)).iterations_done, 5);
}

// Sends a hand-made Hello and returns the coordinator's answer.
proto::coord::CoordinatorMessage HelloAnswer(Listener& listener, uint32_t version,
                                             proto::coord::Role role, std::string* error) {
  Channel client(Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS));
  proto::coord::CoordinatorMessage hello;
  hello.mutable_hello()->set_protocol_version(version);
  hello.mutable_hello()->set_scenario_hash(kHash);
  hello.mutable_hello()->set_role(role);
  hello.mutable_hello()->set_connector_name("old");
  client.Send(hello);
  try {
    AcceptConnector(Channel(listener.Accept(MonotonicNowNs() + kNsPerS)), Expect(),
                    Within(kNsPerS));
  } catch (const Error& e) {
    *error = e.what();
  }
  proto::coord::CoordinatorMessage answer;
  client.Receive(&answer, MonotonicNowNs() + kNsPerS);
  return answer;
}

TEST(Coordinator, HandshakeRefusesAnotherProtocolVersionOrNoRole) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  std::string error;
  const auto answer = HelloAnswer(listener, 99, proto::coord::ROLE_NETWORK, &error);
  EXPECT_EQ(error, "network connector 'old' speaks protocol version 99, the coordinator 1");
  EXPECT_EQ(answer.error().message(), error);
  const auto no_role = HelloAnswer(listener, 1, proto::coord::ROLE_UNSPECIFIED, &error);
  EXPECT_EQ(error, "connector 'old' has no role (physics or network)");
  EXPECT_EQ(no_role.error().message(), error);
}

TEST(Coordinator, SecondConnectorOfARoleIsRefusedByName) {
  Listener listener(ParseEndpoint("unix:/tmp/sitlnet-coord-dup-" + std::to_string(getpid())));
  SyntheticPhysics first_sim(Robots(1));
  SyntheticPhysics second_sim(Robots(1));
  ConnectorThread first(listener.endpoint(), &first_sim, {"phys0", Role::kPhysics, kHash, {}});
  ConnectorThread second(listener.endpoint(), &second_sim, {"phys1", Role::kPhysics, kHash, {}});
  try {
    AcceptConnectors(listener, Expect(), Within(5 * kNsPerS));
    FAIL();
  } catch (const Error& e) {
    // Either may connect first.
    const std::string what = e.what();
    EXPECT_TRUE(what ==
                    "a second physics connector 'phys1' connected; already have physics "
                    "connector 'phys0'" ||
                what ==
                    "a second physics connector 'phys0' connected; already have physics "
                    "connector 'phys1'")
        << what;
  }
}

TEST(Coordinator, MissingConnectorTimesOutNamingTheRole) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
  try {
    AcceptConnectors(listener, Expect(), Within(200 * kNsPerMs));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "no physics connector connected to " +
                                         listener.endpoint().ToString() + " within 200 ms");
  }
}

// A physics simulator that never finishes iteration `stuck_at` until released.
// `sitlnet run --remote network` waits for one network connector: a physics
// one is refused by name on both sides; a stray connection before it is
// skipped; none at all times out naming the role.
TEST(Coordinator, AcceptConnectorOfRoleRefusesTheOtherRoleAndSkipsStrays) {
  Listener listener(ParseEndpoint("127.0.0.1:0"));
  UniqueFd stray = Connect(listener.endpoint(), MonotonicNowNs() + kNsPerS);
  stray.Reset();
  SyntheticPhysics physics_sim(Robots(1));
  ConnectorThread phys(listener.endpoint(), &physics_sim, {"phys0", Role::kPhysics, kHash, {}});
  const std::string expected =
      "physics connector 'phys0' connected, but this coordinator waits for a network connector";
  try {
    AcceptConnectorOfRole(listener, Role::kNetwork, Expect(), Within(5 * kNsPerS));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(e.what(), expected);
  }
  phys.Join();
  EXPECT_EQ(phys.error(), "the coordinator refused: " + expected);

  SyntheticNetwork network_sim(Robots(1));
  ConnectorThread net(listener.endpoint(), &network_sim, {"net0", Role::kNetwork, kHash, {}});
  auto network = AcceptConnectorOfRole(listener, Role::kNetwork, Expect(), Within(5 * kNsPerS));
  ASSERT_TRUE(network);
  EXPECT_EQ(network->Describe(), "network connector 'net0'");
  network->Stop("done");
  net.Join();

  try {
    AcceptConnectorOfRole(listener, Role::kNetwork, Expect(), Within(100 * kNsPerMs));
    FAIL();
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "no network connector connected to " +
                                         listener.endpoint().ToString() + " within 100 ms");
  }
}

}  // namespace
}  // namespace sitlnet::coordinator
