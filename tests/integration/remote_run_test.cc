// `sitlnet run --listen ... --remote network` with the medium model in a
// second process, `sitlnet medium --connect`, over TCP on 127.0.0.1
// (docs/coordinator.md, "A connector on another host"): the co-simulation is
// the same run, byte for byte (issue 6's correctness principle), and every
// failure of the link is one line, a non-zero exit and nothing left behind.
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

constexpr TimeNs kRunTimeoutNs = 120 * kNsPerS;

struct RemoteScenario {
  std::string name;
  std::string path;
};

// Two flocker robots (they beacon on wlan0 and fly on the states), a scenario
// of this process's own ("rr<pid><slot>", own subnets).
RemoteScenario WriteScenario(int slot) {
  const unsigned pid = static_cast<unsigned>(getpid());
  RemoteScenario s;
  s.name = "rr" + std::to_string(pid % 10000) + std::to_string(slot);
  const std::string third = std::to_string(pid % 250);
  s.path = TempDir() + "/" + s.name + ".textproto";
  std::ofstream(s.path) << "name: \"" << s.name << "\"\n"
                        << "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"flocker\" "
                           "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
                        << "robot { name: \"b\" position_m { x: 0 y: 6 z: 0.2 } image: \"flocker\" "
                           "args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
                        << "addresses { wlan_subnet: \"10." << 230 + slot << "." << third
                        << ".0/24\" ctl_subnet: \"10." << 210 + slot << "." << third
                        << ".0/24\" }\n"
                        << "timing { duration_ms: 3000 }\n";
  return s;
}

std::vector<std::string> RunArgs(const RemoteScenario& s, const std::string& out,
                                 std::vector<std::string> extra) {
  std::vector<std::string> argv = {SitlnetBinary(), "run",      s.path,    "--out", out,
                                   "--no-progress", "--pacing", "lockstep"};
  argv.insert(argv.end(), extra.begin(), extra.end());
  return argv;
}

// Starts `sitlnet run ... --listen 127.0.0.1:0 --remote network` and returns
// the port it printed (the kernel picked a free one).
std::string StartListeningRun(Child& run) {
  const std::string marker = "for the network connector on 127.0.0.1:";
  if (!run.WaitForOutput(true, " (sitlnet medium", 30 * kNsPerS)) return "";
  const size_t at = run.err().find(marker);
  if (at == std::string::npos) return "";
  const size_t begin = at + marker.size();
  return run.err().substr(begin, run.err().find(' ', begin) - begin);
}

// Lines of `text` that start with `prefix`.
std::vector<std::string> LinesStartingWith(const std::string& text, const std::string& prefix) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind(prefix, 0) == 0) lines.push_back(line);
  }
  return lines;
}

void ExpectNothingLeft(const std::string& name) {
  EXPECT_FALSE(StateExists(name)) << name;
  const std::vector<std::string> up = ListScenarios();
  EXPECT_EQ(std::find(up.begin(), up.end(), name), up.end()) << name;
  for (const char* robot : {"a", "b"}) EXPECT_FALSE(NetnsExists(name + "-" + robot));
  EXPECT_FALSE(NetnsExists(CtlNetnsName(name))) << name;  // The root sides went with it.
}

TEST(RemoteRunTest, MediumInAnotherProcessOverTcpGivesTheSameRunByteForByte) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RemoteScenario scenario = WriteScenario(0);
  DownGuard guard(scenario.name);
  const std::string base = TempDir() + "/" + scenario.name + "-out";
  const CommandResult local =
      RunCommand(RunArgs(scenario, base + "-local", {"--seed", "5"}), kRunTimeoutNs);
  ASSERT_EQ(local.exit_code, 0) << local.err;
  ExpectNothingLeft(scenario.name);

  Child run(RunArgs(scenario, base + "-remote",
                    {"--seed", "5", "--listen", "127.0.0.1:0", "--remote", "network"}));
  const std::string port = StartListeningRun(run);
  ASSERT_FALSE(port.empty()) << run.err();
  Child medium(
      {SitlnetBinary(), "medium", scenario.path, "--connect", "127.0.0.1:" + port, "--seed", "5"});
  ASSERT_EQ(run.Wait(kRunTimeoutNs), 0) << run.err();
  ASSERT_EQ(medium.Wait(kRunTimeoutNs), 0) << medium.err();
  EXPECT_NE(medium.err().find("stopped: run finished"), std::string::npos) << medium.err();
  EXPECT_NE(run.err().find("medium link to network connector 'medium@"), std::string::npos)
      << run.err();

  const std::string trajectories = ReadAll(base + "-local/trajectories.csv");
  const std::string pcap = ReadAll(base + "-local/medium.pcap");
  // 3 s at 10 Hz for 2 robots plus t=0 and the header; the robots beaconed.
  EXPECT_GE(std::count(trajectories.begin(), trajectories.end(), '\n'), 60);
  EXPECT_GT(pcap.size(), 24u + 20 * 50u);
  EXPECT_EQ(trajectories, ReadAll(base + "-remote/trajectories.csv"));
  EXPECT_EQ(pcap, ReadAll(base + "-remote/medium.pcap"));
  EXPECT_EQ(ReadAll(base + "-local/deliveries.csv"), ReadAll(base + "-remote/deliveries.csv"));
  ExpectNothingLeft(scenario.name);
}

TEST(RemoteRunTest, AnotherSeedIsRefusedWithBothHashesOnOneLineAndNothingIsCreated) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RemoteScenario scenario = WriteScenario(1);
  DownGuard guard(scenario.name);
  Child run(RunArgs(scenario, TempDir() + "/" + scenario.name + "-out",
                    {"--seed", "5", "--listen", "127.0.0.1:0", "--remote", "network"}));
  const std::string port = StartListeningRun(run);
  ASSERT_FALSE(port.empty()) << run.err();
  Child medium(
      {SitlnetBinary(), "medium", scenario.path, "--connect", "127.0.0.1:" + port, "--seed", "6"});
  EXPECT_EQ(run.Wait(kRunTimeoutNs), 1) << run.err();
  EXPECT_EQ(medium.Wait(kRunTimeoutNs), 1) << medium.err();
  for (const auto& [who, err] :
       {std::pair<std::string, std::string>{"run", run.err()}, {"medium", medium.err()}}) {
    const std::vector<std::string> errors = LinesStartingWith(err, "sitlnet " + who + ": ");
    ASSERT_FALSE(errors.empty()) << err;
    const std::string& last = errors.back();
    EXPECT_NE(last.find("network connector 'medium@"), std::string::npos) << last;
    EXPECT_NE(last.find("loaded a different scenario: hash 0x"), std::string::npos) << last;
    EXPECT_NE(last.find("the coordinator's is 0x"), std::string::npos) << last;
  }
  // Refused before `up`: no namespace was ever created.
  ExpectNothingLeft(scenario.name);
}

TEST(RemoteRunTest, MediumKilledMidRunStopsTheRunWithItsNameAndLeavesNothing) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RemoteScenario scenario = WriteScenario(2);
  DownGuard guard(scenario.name);
  // Long enough that the run is still going when the medium dies.
  Child run(RunArgs(scenario, TempDir() + "/" + scenario.name + "-out",
                    {"--duration", "600", "--listen", "127.0.0.1:0", "--remote", "network"}));
  const std::string port = StartListeningRun(run);
  ASSERT_FALSE(port.empty()) << run.err();
  Child medium({SitlnetBinary(), "medium", scenario.path, "--connect", "127.0.0.1:" + port});
  ASSERT_TRUE(run.WaitForOutput(true, "robots up", 30 * kNsPerS)) << run.err();
  kill(medium.pid(), SIGKILL);
  EXPECT_EQ(medium.Wait(kRunTimeoutNs), 128 + SIGKILL);
  EXPECT_EQ(run.Wait(kRunTimeoutNs), 1) << run.err();
  std::vector<std::string> errors = LinesStartingWith(run.err(), "sitlnet run: network");
  std::erase_if(errors, [](const std::string& line) { return line.ends_with(" connected"); });
  ASSERT_EQ(errors.size(), 1u) << run.err();
  EXPECT_NE(errors[0].find("'medium@"), std::string::npos) << errors[0];
  EXPECT_NE(errors[0].find("connector crashed or exited"), std::string::npos) << errors[0];
  ExpectNothingLeft(scenario.name);
}

// Issue 17, finding 4: the remote medium peer is authenticated with a shared secret. A medium
// with another secret or none is refused (the run warns and goes on waiting), the one with the
// secret runs; a run that listens where other hosts can reach it needs a secret.
TEST(RemoteRunTest, ASharedSecretKeepsOutMediaWithoutItAndLetsTheRightOneIn) {
  SITLNET_REQUIRE_NNS_PRIVILEGES();
  const RemoteScenario scenario = WriteScenario(4);
  DownGuard guard(scenario.name);
  const std::string key = TempDir() + "/" + scenario.name + ".key";
  const std::string other_key = TempDir() + "/" + scenario.name + ".other.key";
  std::ofstream(key) << "a shared secret of at least 16 bytes";
  std::ofstream(other_key) << "another secret, also 16 bytes or more";
  ASSERT_EQ(chmod(key.c_str(), 0600), 0);
  ASSERT_EQ(chmod(other_key.c_str(), 0600), 0);
  const std::string out = TempDir() + "/" + scenario.name + "-out";

  const CommandResult open_run =
      RunCommand(RunArgs(scenario, out, {"--listen", "0.0.0.0:0", "--remote", "network"}));
  EXPECT_NE(open_run.exit_code, 0);
  EXPECT_NE(open_run.err.find("--listen 0.0.0.0:0 can be reached from other hosts: give "
                              "--secret-file PATH"),
            std::string::npos)
      << open_run.err;
  ExpectNothingLeft(scenario.name);

  Child run(RunArgs(scenario, out,
                    {"--listen", "127.0.0.1:0", "--remote", "network", "--secret-file", key}));
  const std::string port = StartListeningRun(run);
  ASSERT_FALSE(port.empty()) << run.err();
  const std::vector<std::string> medium = {SitlnetBinary(), "medium", scenario.path, "--connect",
                                           "127.0.0.1:" + port};
  std::vector<std::string> with_other = medium;
  with_other.insert(with_other.end(), {"--secret-file", other_key});
  const CommandResult other = RunCommand(with_other, kRunTimeoutNs);
  EXPECT_EQ(other.exit_code, 1) << other.err;
  EXPECT_NE(other.err.find("the coordinator failed to prove the shared secret"), std::string::npos)
      << other.err;
  const CommandResult none = RunCommand(medium, kRunTimeoutNs);
  EXPECT_EQ(none.exit_code, 1) << none.err;
  EXPECT_NE(none.err.find("did not authenticate: this coordinator needs the shared secret"),
            std::string::npos)
      << none.err;
  std::vector<std::string> with_key = medium;
  with_key.insert(with_key.end(), {"--secret-file", key});
  const CommandResult right = RunCommand(with_key, kRunTimeoutNs);
  EXPECT_EQ(right.exit_code, 0) << right.err;
  ASSERT_EQ(run.Wait(kRunTimeoutNs), 0) << run.err();
  EXPECT_EQ(LinesStartingWith(run.err(), "sitlnet: warning: ignored a connection").size(), 2u)
      << run.err();
  ExpectNothingLeft(scenario.name);
  RunCommand({"rm", "-rf", out, key, other_key});
}

TEST(RemoteRunTest, UnreachableCoordinatorAndRealtimePacingAreOneLineErrors) {
  // A bound TCP port that does not listen: connect() is refused at once.
  const int holder = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(holder, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(holder, reinterpret_cast<sockaddr*>(&address), sizeof address), 0);
  socklen_t length = sizeof address;
  getsockname(holder, reinterpret_cast<sockaddr*>(&address), &length);
  const RemoteScenario scenario = WriteScenario(3);
  const CommandResult medium = RunCommand({SitlnetBinary(), "medium", scenario.path, "--connect",
                                           "127.0.0.1:" + std::to_string(ntohs(address.sin_port)),
                                           "--connect-timeout", "0.3"});
  close(holder);
  EXPECT_EQ(medium.exit_code, 1) << medium.err;
  const std::vector<std::string> errors =
      LinesStartingWith(medium.err, "sitlnet medium: cannot reach the coordinator");
  ASSERT_EQ(errors.size(), 1u) << medium.err;
  EXPECT_NE(errors[0].find("refused"), std::string::npos) << errors[0];

  SITLNET_REQUIRE_NNS_PRIVILEGES();
  std::vector<std::string> argv = RunArgs(scenario, TempDir() + "/" + scenario.name + "-out",
                                          {"--listen", "127.0.0.1:0", "--remote", "network"});
  argv[std::find(argv.begin(), argv.end(), "lockstep") - argv.begin()] = "realtime";
  const CommandResult run = RunCommand(argv);
  EXPECT_EQ(run.exit_code, 2) << run.err;
  EXPECT_NE(run.err.find("needs lockstep pacing"), std::string::npos) << run.err;
  ExpectNothingLeft(scenario.name);
}

}  // namespace
}  // namespace sitlnet::nns::testing
