// OCI container images as robot images (docs/containers.md): podman runs them in the robots'
// network namespaces. Two images are built here from the Debian base of scripts/container-base:
// one with Debian's iperf3 and ping, one with the project's flocker. Oracles: traffic on the
// medium's own capture (tshark), a lockstep run byte-identical to the same run with flocker on
// the host, and `podman container exists` after `down` of a killed run.
#include <signal.h>
#include <unistd.h>

#include <fstream>
#include <mutex>

#include "tests/integration/nns_test_util.h"

namespace sitlnet::nns::testing {
namespace {

using integration_test::IsMinCapsPass;
using integration_test::SourceDir;

struct TestImages {
  std::string error;  // Why they could not be built; empty when they were.
  std::string net;    // iperf3 + ping
  std::string flocker;
};

void RemoveTestImages();

// Built once per test binary, removed at its exit.
const TestImages& Images() {
  static TestImages images;
  static std::once_flag once;
  std::call_once(once, [] {
    const CommandResult base = RunCommand({SourceDir() + "/scripts/container-base"}, 600 * kNsPerS);
    if (base.exit_code != 0) {
      images.error = "scripts/container-base failed: " + base.err;
      return;
    }
    const std::string base_image = base.out.substr(0, base.out.find('\n'));
    const std::string tag = std::to_string(getpid());
    const std::string dir = TempDir() + "/container-images";
    RunCommand({"mkdir", "-p", dir + "/net", dir + "/flocker"});
    std::ofstream(dir + "/net/Containerfile")
        << "FROM " << base_image << "\n"
        << "RUN apt-get update -qq && apt-get install -y -qq --no-install-recommends iperf3 "
           "iputils-ping >/dev/null && rm -rf /var/lib/apt/lists/*\n"
        // Debian's ping carries the file capability cap_net_raw, which no container of a robot
        // has: a copy without it uses the ICMP datagram sockets `up` allows in every robot.
        << "RUN cp /usr/bin/ping /usr/local/bin/ping\n";
    // flocker's shared libraries beyond the base: libprotobuf (ldd build/bin/flocker).
    std::ofstream(dir + "/flocker/Containerfile")
        << "FROM " << base_image << "\n"
        << "RUN apt-get update -qq && apt-get install -y -qq --no-install-recommends "
           "libprotobuf32 zlib1g >/dev/null && rm -rf /var/lib/apt/lists/*\n"
        << "COPY flocker /usr/local/bin/flocker\n";
    const std::string bin = SitlnetBinary().substr(0, SitlnetBinary().rfind('/'));
    RunCommand({"cp", bin + "/flocker", dir + "/flocker/flocker"});
    for (auto [name, image] : {std::pair{"net", &images.net}, {"flocker", &images.flocker}}) {
      *image = "localhost/sitlnet-test-" + std::string(name) + ":" + tag;
      const CommandResult build =
          RunCommand({"podman", "build", "-q", "-t", *image, dir + "/" + name}, 600 * kNsPerS);
      if (build.exit_code != 0) {
        images.error = "podman build of " + *image + " failed: " + build.err;
        return;
      }
    }
    std::atexit(RemoveTestImages);
  });
  return images;
}

void RemoveTestImages() {
  RunCommand({"podman", "rmi", "--force", Images().net, Images().flocker}, 120 * kNsPerS);
}

// "no podman" when podman is not installed (scripts/setup's group "containers"), else "".
std::string PodmanMissing() {
  return RunCommand({"podman", "--version"}).exit_code == 0 ? "" : "no podman";
}

// Skips or fails (CI=true) when podman cannot run containers here.
#define SITLNET_REQUIRE_CONTAINER_IMAGES()                                                  \
  do {                                                                                      \
    SITLNET_REQUIRE_NNS_PRIVILEGES();                                                       \
    if (IsMinCapsPass()) {                                                                  \
      GTEST_SKIP() << "podman needs more than CAP_NET_ADMIN + CAP_SYS_ADMIN to create a "   \
                      "container (CAP_SETUID, CAP_CHOWN, ... for its processes and files)"; \
    }                                                                                       \
    SITLNET_REQUIRE_SETUP_GROUP("containers", PodmanMissing());                             \
    if (const TestImages& images = Images(); !images.error.empty()) {                       \
      if (IsCi()) FAIL() << images.error;                                                   \
      GTEST_SKIP() << images.error;                                                         \
    }                                                                                       \
  } while (0)

struct Scenario {
  std::string name;
  std::string path;
  std::string wlan_prefix;  // "10.x.y."
};
// Subnets of this process and slot.
std::string WlanPrefix(int slot) {
  return "10." + std::to_string(230 + slot) + "." + std::to_string(getpid() % 250) + ".";
}
Scenario WriteScenario(int slot, const std::string& robots, const std::string& extra) {
  const unsigned pid = static_cast<unsigned>(getpid());
  Scenario s;
  s.name = "oc" + std::to_string(pid % 10000) + std::to_string(slot);
  const std::string third = std::to_string(pid % 250);
  s.wlan_prefix = WlanPrefix(slot);
  s.path = TempDir() + "/" + s.name + ".textproto";
  std::ofstream(s.path) << "name: \"" << s.name << "\"\n"
                        << robots << "addresses { wlan_subnet: \"" << s.wlan_prefix
                        << "0/24\" ctl_subnet: \"10." << 210 + slot << "." << third << ".0/24\" }\n"
                        << extra;
  return s;
}

// The containers podman knows for `scenario` (label set by sitlnet), running or not.
std::string ContainersOf(const std::string& scenario) {
  return RunCommand({"podman", "ps", "--all", "--quiet", "--filter",
                     "label=io.sitlnet.scenario=" + scenario})
      .out;
}

void ExpectNothingLeft(const Scenario& scenario, const std::vector<std::string>& robots) {
  EXPECT_FALSE(StateExists(scenario.name));
  for (const std::string& robot : robots) {
    EXPECT_FALSE(NetnsExists(scenario.name + "-" + robot)) << robot;
    EXPECT_EQ(
        RunCommand({"podman", "container", "exists", "sitlnet-" + scenario.name + "-" + robot})
            .exit_code,
        1)
        << "container of robot " << robot << " left";
  }
  EXPECT_EQ(ContainersOf(scenario.name), "");
}

TEST(ContainerImageTest, Iperf3AndPingInContainersCrossTheMedium) {
  SITLNET_REQUIRE_CONTAINER_IMAGES();
  const std::string manifest = WriteImageManifest(
      "container_net", "container_image: \"" + Images().net + "\"\ncommand: \"${ARGS}\"\n");
  // a is .1 and b .2 of the scenario's wlan subnet (robots in order).
  const std::string server = WlanPrefix(0) + "1";
  const Scenario scenario =
      WriteScenario(0,
                    "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"" + manifest +
                        "\" args: [\"iperf3\", \"-s\", \"-1\"] }\n"
                        "robot { name: \"b\" position_m { x: 5 y: 0 z: 0.2 } image: \"" +
                        manifest +
                        "\" args: [\"sh\", \"-c\", \"echo robot=$SITLNET_ROBOT host=$(cat "
                        "/proc/sys/kernel/hostname); sleep 1; ping -n -c 5 -i 0.2 " +
                        server + " && iperf3 -c " + server + " -u -b 2M -t 2\"] }\n",
                    "timing { duration_ms: 9000 pacing: PACING_REALTIME }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  const CommandResult run = RunCommand(
      {SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"}, 300 * kNsPerS);
  ASSERT_EQ(run.exit_code, 0) << run.err << ReadAll(out + "/robots/a.log")
                              << ReadAll(out + "/robots/b.log");
  const std::string client_log = ReadAll(out + "/robots/b.log");
  // The robot's environment and hostname reached the container.
  EXPECT_NE(client_log.find("robot=b host=b"), std::string::npos) << client_log;
  EXPECT_NE(client_log.find("5 received"), std::string::npos) << client_log;
  EXPECT_NE(client_log.find("receiver"), std::string::npos) << client_log;
  // The medium carried them: echo requests b -> a and iperf3's datagrams in its own capture.
  const auto count = [&](const std::string& filter) {
    const CommandResult tshark = RunCommand(
        {"tshark", "-r", out + "/medium.pcap", "-Y", filter, "-T", "fields", "-e", "frame.number"},
        60 * kNsPerS);
    EXPECT_EQ(tshark.exit_code, 0) << tshark.err;
    return std::count(tshark.out.begin(), tshark.out.end(), '\n');
  };
  const std::string a = scenario.wlan_prefix + "1", b = scenario.wlan_prefix + "2";
  EXPECT_EQ(count("icmp.type == 8 && ip.src == " + b + " && ip.dst == " + a), 5);
  // 2 Mbit/s for 2 s in iperf3's default 1448-byte datagrams: about 345.
  EXPECT_GT(count("udp.dstport == 5201 && ip.src == " + b), 300);
  ExpectNothingLeft(scenario, {"a", "b"});
  RunCommand({"rm", "-rf", out});
}

// The same lockstep run with flocker on the host and in a container: the container changes
// nothing the simulation sees (byte-identical trajectories and medium capture).
TEST(ContainerImageTest, FlockerInAContainerFliesExactlyAsOnTheHost) {
  SITLNET_REQUIRE_CONTAINER_IMAGES();
  const std::string manifest =
      WriteImageManifest("container_flocker", "container_image: \"" + Images().flocker +
                                                  "\"\ncommand: [\"flocker\", \"--airframe\", "
                                                  "\"${AIRFRAME}\", \"${ARGS}\"]\nready_log_line: "
                                                  "\"t=\"\n");
  const auto robots = [](const std::string& image) {
    return "robot { name: \"a\" position_m { x: 0 y: 0 z: 0.2 } image: \"" + image +
           "\" args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n"
           "robot { name: \"b\" position_m { x: 0 y: 6 z: 0.2 } image: \"" +
           image + "\" args: [\"--target\", \"40,0\"] lidar { rays: 8 } }\n";
  };
  const std::string timing = "timing { duration_ms: 5000 }\n";
  // The same scenario (name, subnets, seed) twice: the name is in the run's records.
  std::string outs[2];
  Scenario scenario;
  for (int i = 0; i < 2; ++i) {
    scenario = WriteScenario(1, robots(i == 0 ? "flocker" : manifest), timing);
    DownGuard guard(scenario.name);
    outs[i] = TempDir() + "/" + scenario.name + "-flocker" + std::to_string(i);
    const CommandResult run = RunCommand({SitlnetBinary(), "run", scenario.path, "--out", outs[i],
                                          "--no-progress", "--pacing", "lockstep", "--seed", "5"},
                                         300 * kNsPerS);
    ASSERT_EQ(run.exit_code, 0) << run.err << ReadAll(outs[i] + "/robots/a.log");
  }
  const std::string host_trajectories = ReadAll(outs[0] + "/trajectories.csv");
  // 5 s at 10 Hz for 2 robots plus the header: the robots flew.
  ASSERT_GE(std::count(host_trajectories.begin(), host_trajectories.end(), '\n'), 100);
  EXPECT_EQ(ReadAll(outs[1] + "/trajectories.csv"), host_trajectories);
  EXPECT_EQ(ReadAll(outs[1] + "/medium.pcap"), ReadAll(outs[0] + "/medium.pcap"));
  EXPECT_NE(ReadAll(outs[1] + "/robots/a.log").find("t="), std::string::npos);
  ExpectNothingLeft(scenario, {"a", "b"});
  RunCommand({"rm", "-rf", outs[0], outs[1]});
}

// kill -9 of `sitlnet run` leaves its containers running (podman's, not the run's children);
// `sitlnet down` removes them by name.
TEST(ContainerImageTest, DownRemovesTheContainersOfAKilledRun) {
  SITLNET_REQUIRE_CONTAINER_IMAGES();
  const std::string manifest = WriteImageManifest(
      "container_sleeper", "container_image: \"" + Images().net +
                               "\"\ncommand: [\"sh\", \"-c\", \"echo up; exec sleep 600\"]\n");
  const Scenario scenario =
      WriteScenario(3, "robot { name: \"a\" image: \"" + manifest + "\" }\nrobot { name: \"b\" }\n",
                    "timing { duration_ms: 600000 pacing: PACING_REALTIME }\n");
  DownGuard guard(scenario.name);
  const std::string out = TempDir() + "/" + scenario.name + "-out";
  Child run({SitlnetBinary(), "run", scenario.path, "--out", out, "--no-progress"});
  const std::string container = "sitlnet-" + scenario.name + "-a";
  ASSERT_TRUE(WaitForFiles(
      out + "/robots",
      [&] { return ReadAll(out + "/robots/a.log").find("up\n") != std::string::npos; },
      120 * kNsPerS))
      << ReadAll(out + "/robots/a.log") << run.err();
  ASSERT_EQ(kill(run.pid(), SIGKILL), 0);
  ASSERT_EQ(run.Wait(10 * kNsPerS), 128 + SIGKILL);
  // Still there: the run's end did not take it along.
  EXPECT_EQ(RunCommand({"podman", "container", "exists", container}).exit_code, 0);
  const CommandResult down = RunCommand({SitlnetBinary(), "down", scenario.name}, 120 * kNsPerS);
  ASSERT_EQ(down.exit_code, 0) << down.err;
  EXPECT_NE(down.out.find("1 containers removed"), std::string::npos) << down.out;
  ExpectNothingLeft(scenario, {"a", "b"});
  RunCommand({"rm", "-rf", out});
}

}  // namespace
}  // namespace sitlnet::nns::testing
