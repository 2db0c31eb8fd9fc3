#include "robot_images/robot_images.h"

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/syscall.h>
#include <sys/time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>

#include "robot_images/images_internal.h"

namespace sitlnet::images {
namespace {

constexpr const char* kSocketTimeoutsModule = SITLNET_SOCKET_TIMEOUTS_PATH;

std::string ImagesRoot() {
  const char* dir = std::getenv("SITLNET_SOURCE_DIR");
  return std::string(dir ? dir : ".") + "/robot_images";
}

LaunchContext Context() {
  LaunchContext context;
  context.sitlnet_bin_dir = "/opt/sitlnet/bin";
  context.scenario = "demo";
  context.robot = "uav2";
  context.robot_index = 1;
  context.robot_args = {"--target", "120,0"};
  context.airframe_text = "mass_kg: 2";
  return context;
}

// What LoadImage says of a manifest file `path` holding `text`; "" when it loads.
std::string LoadError(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
  try {
    LoadImage("", path);
  } catch (const Error& error) {
    return error.what();
  }
  return "";
}

TEST(ImageTest, ShippedImagesLoad) {
  for (const char* name :
       {"flocker", "flocker_video", "iperf", "shell", "attacker", "babel", "test_autopilot",
        "arducopter", "px4"}) {
    const Image image = LoadImage(ImagesRoot(), name);
    EXPECT_EQ(image.manifest.name(), name);
  }
}

TEST(ImageTest, ExpandsPlaceholdersAndSplicesArgs) {
  const Image image = LoadImage(ImagesRoot(), "flocker");
  const std::vector<std::string> argv = ExpandCommand(image, Context());
  EXPECT_EQ(argv, (std::vector<std::string>{"/opt/sitlnet/bin/flocker", "--airframe", "mass_kg: 2",
                                            "--target", "120,0"}));
}

// Where an autopilot is built differs from host to host: ${env:NAME} reads sitlnet's environment.
TEST(ImageTest, EnvPlaceholderReadsSitlnetsEnvironmentAndNamesAnUnsetVariable) {
  const std::string path = ::testing::TempDir() + "/env_image.textproto";
  std::ofstream(path) << "name: \"x\"\ncommand: \"${env:SITLNET_TEST_DIR}/bin/px4\"\n";
  const Image image = LoadImage("", path);
  ASSERT_EQ(setenv("SITLNET_TEST_DIR", "/opt/px4", 1), 0);
  EXPECT_EQ(ExpandCommand(image, Context()), std::vector<std::string>{"/opt/px4/bin/px4"});
  ASSERT_EQ(unsetenv("SITLNET_TEST_DIR"), 0);
  try {
    ExpandCommand(image, Context());
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              path + ": ${env:SITLNET_TEST_DIR}: SITLNET_TEST_DIR is not set in sitlnet's "
                     "environment (the manifest's comments say what it names)");
  }
  std::remove(path.c_str());
}

// The ArduCopter manifest takes its folder from SITLNET_ARDUPILOT_DIR (the tests and .ci/run
// set it), lists the binary and the parameters as files, and starts at the scenario's origin.
TEST(ImageTest, ArduCopterTakesItsFolderFromTheEnvironmentAndItsHomeFromTheOrigin) {
  const Image image = LoadImage(ImagesRoot(), "arducopter");
  LaunchContext context = Context();
  context.geodetic_origin = "47.397742000,8.545594000,488.000";
  const char* before = std::getenv("SITLNET_ARDUPILOT_DIR");
  const std::string kept = before != nullptr ? before : "";
  ASSERT_EQ(setenv("SITLNET_ARDUPILOT_DIR", "/tmp/ardupilot-x", 1), 0);
  const std::vector<std::string> argv = ExpandCommand(image, context);
  ASSERT_GE(argv.size(), 3u);
  EXPECT_NE(argv[2].find("--home \"47.397742000,8.545594000,488.000,0\""), std::string::npos)
      << argv[2];
  EXPECT_EQ(ExpandEnv(image, context), std::vector<std::string>{"ARDUPILOT_DIR=/tmp/ardupilot-x"});
  try {
    CheckFiles(image, context);
    FAIL();
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(),
                 "robot \"uav2\": image \"arducopter\" needs /tmp/ardupilot-x/bin/arducopter, "
                 "which does not exist");
  }
  ASSERT_EQ(unsetenv("SITLNET_ARDUPILOT_DIR"), 0);
  try {
    ExpandEnv(image, context);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()),
              image.manifest_path +
                  ": ${env:SITLNET_ARDUPILOT_DIR}: SITLNET_ARDUPILOT_DIR is not set in sitlnet's "
                  "environment (the manifest's comments say what it names)");
  }
  if (before != nullptr) setenv("SITLNET_ARDUPILOT_DIR", kept.c_str(), 1);
}

TEST(ImageTest, MissingFileNamesRobotAndPath) {
  const Image image = LoadImage(ImagesRoot(), "flocker");
  try {
    CheckFiles(image, Context());
    FAIL();
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(),
                 "robot \"uav2\": image \"flocker\" needs /opt/sitlnet/bin/flocker, which does not "
                 "exist");
  }
}

// The shipped PX4 manifest takes PX4's folder from SITLNET_PX4_DIR and needs it (`files`): a
// folder that is there is accepted, a missing one is refused naming the robot and the path.
TEST(ImageTest, Px4ManifestTakesItsFolderFromSitlnetPx4Dir) {
  const char* before = std::getenv("SITLNET_PX4_DIR");
  const std::string saved = before ? before : "";
  const Image image = LoadImage(ImagesRoot(), "px4");
  setenv("SITLNET_PX4_DIR", ::testing::TempDir().c_str(), 1);
  const std::vector<std::string> env = ExpandEnv(image, Context());
  EXPECT_NE(std::find(env.begin(), env.end(), "PX4_DIR=" + ::testing::TempDir()), env.end());
  EXPECT_NO_THROW(CheckFiles(image, Context()));
  setenv("SITLNET_PX4_DIR", "/nonexistent/px4", 1);
  try {
    CheckFiles(image, Context());
    ADD_FAILURE() << "a missing PX4 folder was accepted";
  } catch (const Error& error) {
    EXPECT_STREQ(error.what(),
                 "robot \"uav2\": image \"px4\" needs /nonexistent/px4, which does not exist");
  }
  if (before != nullptr) {
    setenv("SITLNET_PX4_DIR", saved.c_str(), 1);
  } else {
    unsetenv("SITLNET_PX4_DIR");
  }
}

TEST(ImageTest, BadManifestsAreRejectedWithTheirPlace) {
  const std::string path = ::testing::TempDir() + "/bad_image.textproto";
  std::ofstream(path) << "name: \"x\"\ncommand: \"${NOPE}\"\n";
  const Image image = LoadImage("", path);
  EXPECT_THROW(ExpandCommand(image, Context()), Error);
  std::ofstream(path) << "name: \"x\"\ncomand: \"a\"\n";
  try {
    LoadImage("", path);
    FAIL();
  } catch (const Error& error) {
    EXPECT_EQ(std::string(error.what()).rfind(path + ":2:", 0), 0u) << error.what();
  }
  EXPECT_THROW(LoadImage(ImagesRoot(), "no_such_image"), Error);
}

// Each refusal names the manifest and the field; what the sandbox does at run time is attacked
// in tests/integration/isolation_test.cc (AttackerImage*).
TEST(ImageTest, SandboxFieldsThatReachBeyondTheRobotAreRefused) {
  const std::string path = ::testing::TempDir() + "/sandbox_image.textproto";
  const auto refusal = [&](const std::string& fields) {
    return LoadError(path, "name: \"x\"\ncommand: \"/bin/true\"\n" + fields);
  };
  EXPECT_EQ(refusal("capabilities: \"CAP_NET_ADMIN\" capabilities: \"CAP_NET_RAW\""), "");
  EXPECT_EQ(refusal("writable: \"/srv/logs\" hidden: \"${IMAGE_DIR}/secret\""), "");
  EXPECT_EQ(refusal("sandbox: NONE user: \"nobody\" capabilities: \"CAP_NET_RAW\""), "");
  for (const char* reaching :
       {"CAP_SYS_ADMIN", "CAP_DAC_OVERRIDE", "CAP_SYS_PTRACE", "net_admin"}) {
    const std::string error = refusal(std::string("capabilities: \"") + reaching + "\"");
    EXPECT_EQ(error.rfind(path + ": capabilities: \"" + reaching + "\" is not one", 0), 0u)
        << error;
  }
  EXPECT_EQ(
      refusal("writable: \"logs\"").rfind(path + ": writable: \"logs\" is not an absolute", 0), 0u);
  EXPECT_EQ(refusal("sandbox: NONE writable: \"/srv\"").rfind(path + ": writable and hidden", 0),
            0u);
  EXPECT_EQ(
      refusal("sandbox: NONE capabilities: \"CAP_NET_RAW\"").rfind(path + ": capabilities:", 0),
      0u);
  std::remove(path.c_str());
}

// Issue 36: a robot's sandbox keeps /run, /tmp and /var/tmp private and empty, and hides what
// the manifest hides. An image whose program, `files:` entry or preload library the robot would
// not see is refused before it starts, naming the path and the fix.
class VisibilityTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char image_dir[] = "/tmp/sitlnet-visible-image-XXXXXX";
    char program_dir[] = "/tmp/sitlnet-visible-program-XXXXXX";
    ASSERT_NE(mkdtemp(image_dir), nullptr);
    ASSERT_NE(mkdtemp(program_dir), nullptr);
    image_dir_ = image_dir;
    program_dir_ = program_dir;
    program_ = program_dir_ + "/prog";
    std::ofstream(program_) << "#!/bin/sh\nexit 0\n";
    chmod(program_.c_str(), 0755);
  }
  void TearDown() override {
    RunProgramQuietly({"rm", "-rf", image_dir_, program_dir_});
  }
  // What CheckFiles says of an image running `program_` with `fields`; "" when it may run.
  std::string Refusal(const std::string& fields, double realtime_factor = 1.0) {
    const std::string path = image_dir_ + "/image.textproto";
    std::ofstream(path) << "name: \"x\"\ncommand: \"" << program_ << "\"\n" << fields;
    LaunchContext context = Context();
    context.realtime_factor = realtime_factor;
    try {
      CheckFiles(LoadImage("", path), context);
    } catch (const Error& error) {
      return error.what();
    }
    return "";
  }
  std::string image_dir_;
  std::string program_dir_;
  std::string program_;
};

TEST_F(VisibilityTest, WhatTheRobotCannotSeeIsRefusedNamingPathAndFix) {
  const std::string refusal = Refusal("");
  EXPECT_EQ(refusal, "robot \"uav2\": image \"x\" (" + image_dir_ +
                         "/image.textproto): its program " + program_ +
                         " is not visible to it: it lies in /tmp, which the robot's sandbox "
                         "keeps private and empty: list it or its folder in the manifest's "
                         "files:, or move it out of /run, /tmp and /var/tmp");
  EXPECT_EQ(Refusal("files: \"" + program_dir_ + "\"\n"), "");  // A folder,
  EXPECT_EQ(Refusal("files: \"" + program_ + "\"\n"), "");       // or the file itself.
  EXPECT_EQ(Refusal("sandbox: NONE\n"), "");  // The host's files, as they are.
  EXPECT_NE(Refusal("files: \"" + program_dir_ + "\"\nhidden: \"" + program_dir_ + "\"\n")
                .find("its program " + program_ + " is not visible to it: it lies in " +
                      program_dir_ + ", which the manifest hides (hidden:)"),
            std::string::npos);
  // A library the manifest preloads from a private folder: ld.so would skip it with a log line.
  EXPECT_NE(Refusal("files: \"" + program_ + "\"\nenv { name: \"LD_PRELOAD\" value: \"" +
                    program_dir_ + "/lib.so\" }\n")
                .find("preload library " + program_dir_ + "/lib.so is not visible"),
            std::string::npos);
}

TEST_F(VisibilityTest, DilatedRobotWhoseSocketTimeoutsLibraryIsHiddenIsRefusedNotUndilated) {
  const std::string files = "files: \"" + program_dir_ + "\"\n";
  const std::string library_dir = std::string(kSocketTimeoutsModule).substr(
      0, std::string(kSocketTimeoutsModule).rfind('/'));
  EXPECT_EQ(Refusal(files, /*realtime_factor=*/2), "");
  EXPECT_NE(Refusal(files + "hidden: \"" + library_dir + "\"\n", /*realtime_factor=*/2)
                .find(std::string("preload library ") + kSocketTimeoutsModule + " is not visible"),
            std::string::npos);
  // Undilated, the same image loads no library of sitlnet's.
  EXPECT_EQ(Refusal(files + "hidden: \"" + library_dir + "\"\n", /*realtime_factor=*/1), "");
}

// The oracle is bubblewrap itself: the sandbox that ConfinementPrefix builds shows the robot
// exactly what the check lets through, its program in a private folder when `files:` names it,
// and sitlnet's dilated-time libraries wherever sitlnet is built.
TEST_F(VisibilityTest, TheSandboxShowsWhatTheCheckLetsThrough) {
  if (geteuid() != 0 || internal::FindProgram("bwrap").empty()) {
    if (std::getenv("CI") != nullptr && std::string(std::getenv("CI")) == "true") {
      FAIL() << "needs root and bubblewrap (apt-get install bubblewrap)";
    }
    GTEST_SKIP() << "needs root and bubblewrap (apt-get install bubblewrap)";
  }
  const auto robot_reads = [&](const std::string& fields, const std::string& file) {
    const std::string path = image_dir_ + "/image.textproto";
    std::ofstream(path) << "name: \"x\"\ncommand: \"" << program_ << "\"\n" << fields;
    LaunchContext context = Context();
    context.realtime_factor = 2;
    std::vector<std::string> argv =
        internal::ConfinementPrefix(LoadImage("", path), context);
    argv.insert(argv.end(), {"/bin/sh", "-c", "test -r \"$0\"", file});
    return RunProgramQuietly(argv) == 0;
  };
  EXPECT_FALSE(robot_reads("", program_));
  EXPECT_TRUE(robot_reads("files: \"" + program_dir_ + "\"\n", program_));
  EXPECT_TRUE(robot_reads("", kSocketTimeoutsModule));
}

// Issue 42: PX4 asks SCHED_FIFO for its threads and, refused, runs them at normal priority, where
// its HRT thread can miss a timer (robot_images/px4/image.textproto). The oracle is the kernel:
// in the shipped PX4 image's sandbox a process may take SCHED_FIFO; without the capability the
// same sandbox refuses it.
TEST_F(VisibilityTest, ThePx4ImageMayGiveItsThreadsTheRealtimePrioritiesPx4AsksFor) {
  if (geteuid() != 0 || internal::FindProgram("bwrap").empty() ||
      internal::FindProgram("chrt").empty()) {
    if (std::getenv("CI") != nullptr && std::string(std::getenv("CI")) == "true") {
      FAIL() << "needs root, bubblewrap and chrt (apt-get install bubblewrap util-linux)";
    }
    GTEST_SKIP() << "needs root, bubblewrap and chrt (apt-get install bubblewrap util-linux)";
  }
  const char* before = std::getenv("SITLNET_PX4_DIR");
  const std::string saved = before ? before : "";
  setenv("SITLNET_PX4_DIR", program_dir_.c_str(), 1);  // The manifest binds it in (`files`).
  const auto takes_fifo = [](const Image& image) {
    std::vector<std::string> argv = internal::ConfinementPrefix(image, Context());
    argv.insert(argv.end(), {"chrt", "-f", "1", "true"});
    return RunProgramQuietly(argv) == 0;
  };
  EXPECT_TRUE(takes_fifo(LoadImage(ImagesRoot(), "px4")));
  const std::string path = image_dir_ + "/image.textproto";
  std::ofstream(path) << "name: \"x\"\ncommand: \"" << program_ << "\"\n";
  EXPECT_FALSE(takes_fifo(LoadImage("", path)));
  if (before != nullptr) {
    setenv("SITLNET_PX4_DIR", saved.c_str(), 1);
  } else {
    unsetenv("SITLNET_PX4_DIR");
  }
}

// Issue 17: limits a cgroup cannot hold are refused naming the manifest and the field.
TEST(ImageTest, LimitsOutsideWhatACgroupHoldsAreRefused) {
  const std::string path = ::testing::TempDir() + "/limits_image.textproto";
  const auto refusal = [&](const std::string& fields) {
    return LoadError(path, "name: \"x\"\n" + fields);
  };
  EXPECT_EQ(refusal("command: \"/bin/true\" limits { memory_max_mib: 64 pids_max: 16 "
                    "cpu_max_cores: 0.5 }"),
            "");
  EXPECT_EQ(refusal("command: \"/bin/true\" limits { cpu_max_cores: 0 }"), "");
  for (const char* cores : {"nan", "inf", "-1", "2000", "0.001"}) {
    const std::string error =
        refusal(std::string("command: \"/bin/true\" limits { cpu_max_cores: ") + cores + " }");
    EXPECT_EQ(error.rfind(path + ": limits.cpu_max_cores: must be", 0), 0u) << cores << error;
  }
  EXPECT_EQ(refusal("command: \"/bin/true\" limits { memory_max_mib: 2000000 }")
                .rfind(path + ": limits.memory_max_mib: must be", 0),
            0u);
  EXPECT_EQ(refusal("command: \"/bin/true\" limits { pids_max: 5000000 }")
                .rfind(path + ": limits.pids_max: must be", 0),
            0u);
  EXPECT_NE(refusal("container_image: \"px4\" limits { pids_max: 8 }")
                .find("a container image is limited by its engine"),
            std::string::npos);
  std::remove(path.c_str());
}

// Issue 16: a manifest may name an OCI container image instead of a program; fields meant for
// host programs are refused naming the manifest. What podman makes of the arguments is tested
// with real containers in tests/integration/container_image_test.cc.
TEST(ImageTest, ContainerImagesNeedNoCommandAndRefuseHostOnlyFields) {
  const std::string path = ::testing::TempDir() + "/container_image.textproto";
  const auto refusal = [&](const std::string& fields) {
    return LoadError(path, "name: \"x\"\n" + fields);
  };
  EXPECT_EQ(refusal("container_image: \"localhost/px4:1\""), "");
  EXPECT_EQ(refusal("container_image: \"px4\" command: \"px4\" writable: \"/srv\" "
                    "capabilities: \"CAP_NET_RAW\" time: WALL"),
            "");
  EXPECT_EQ(
      refusal("env { name: \"A\" value: \"b\" }").rfind(path + ": image \"x\" has no command", 0),
      0u);
  for (const char* field : {"sandbox: NONE", "hidden: \"/etc\"", "time: DILATED"}) {
    const std::string error = refusal(std::string("container_image: \"px4\" ") + field);
    EXPECT_EQ(error.rfind(path + ": ", 0), 0u) << error;
    EXPECT_NE(error.find("not for a container image"), std::string::npos) << error;
  }
  EXPECT_NE(refusal("container_image: \"--privileged\"").find("not an image name"),
            std::string::npos);
  EXPECT_NE(refusal("container_image: \"px4\" capabilities: \"CAP_SYS_ADMIN\"")
                .find("capabilities: \"CAP_SYS_ADMIN\" is not one"),
            std::string::npos);
  std::remove(path.c_str());
}

// The robot's place reaches the container as it reaches a host program; its clock cannot be
// dilated.
TEST(ImageTest, ContainerRunJoinsTheRobotsNamespaceWithItsEnvironment) {
  const std::string path = ::testing::TempDir() + "/container_run.textproto";
  std::ofstream(path)
      << "name: \"px4\"\ncontainer_image: \"localhost/px4:1\"\n"
         "command: [\"px4\", \"${ARGS}\"]\nenv { name: \"K\" value: \"${ROBOT}\" }\n";
  const Image image = LoadImage("", path);
  LaunchContext context = Context();
  context.physics_address = "10.0.0.1:5600";
  const ContainerTarget target{"/usr/bin/podman", "sitlnet-demo-uav2"};
  const std::vector<std::string> args = internal::ContainerRunArgs(
      image, context, target, ExpandCommand(image, context), ExpandEnv(image, context));
  const auto has_pair = [&](const std::string& option, const std::string& value) {
    for (size_t i = 0; i + 1 < args.size(); ++i) {
      if (args[i] == option && args[i + 1] == value) return true;
    }
    return false;
  };
  EXPECT_EQ(args[0], "/usr/bin/podman");
  EXPECT_TRUE(has_pair("--network", "ns:/run/netns/demo-uav2"));
  EXPECT_TRUE(has_pair("--name", "sitlnet-demo-uav2"));
  EXPECT_TRUE(has_pair("--cap-drop", "ALL"));
  EXPECT_TRUE(has_pair("--pull", "never"));
  for (const char* variable :
       {"SITLNET_SCENARIO=demo", "SITLNET_ROBOT=uav2", "SITLNET_ROBOT_INDEX=1",
        "SITLNET_PHYSICS_ADDR=10.0.0.1:5600", "K=uav2"}) {
    EXPECT_TRUE(has_pair("--env", variable)) << variable;
  }
  // The image, then its command: podman reads no option after the image's name.
  const std::vector<std::string> tail(args.end() - 4, args.end());
  EXPECT_EQ(tail, (std::vector<std::string>{"localhost/px4:1", "px4", "--target", "120,0"}));
  context.realtime_factor = 0.5;
  EXPECT_THROW(internal::ContainerRunArgs(image, context, target, {}, {}), Error);
  std::remove(path.c_str());
}

// Issue 18: which images read the dilated clock, and what sets it up. What it does to real
// programs is measured in tests/integration/run_test.cc (DilatedTime*).
TEST(ImageTest, DilatedTimeIsTheDefaultAwayFromFactorOneAndRefusesWhatItCannotDilate) {
  Image image = LoadImage(ImagesRoot(), "shell");
  LaunchContext context = Context();
  const std::vector<std::string> sh = {"/bin/sh", "-c", "true"};
  context.realtime_factor = 1.0;
  EXPECT_TRUE(internal::DilatedTimeEnvironment(image, context, sh).empty());
  context.realtime_factor = 0;  // Lockstep.
  EXPECT_TRUE(internal::DilatedTimeEnvironment(image, context, sh).empty());
  context.realtime_factor = 0.25;
  const std::vector<std::string> env = internal::DilatedTimeEnvironment(image, context, sh);
  ASSERT_EQ(env.size(), 4u);
  EXPECT_EQ(env[0], std::string("LD_PRELOAD=/usr/lib/") + CMAKE_LIBRARY_ARCHITECTURE +
                        "/faketime/libfaketimeMT.so.1:" + kSocketTimeoutsModule);
  EXPECT_EQ(env[1], "FAKETIME=+0 x0.25");  // libfaketime's README: offset, then speed.
  EXPECT_EQ(env[2], "SITLNET_TIME_FACTOR=0.25");
  EXPECT_EQ(env[3], "FAKETIME_DONT_RESET=1");
  image.manifest.set_time(proto::ImageManifest::WALL);
  EXPECT_TRUE(internal::DilatedTimeEnvironment(image, context, sh).empty());
  image.manifest.set_time(proto::ImageManifest::DILATED);
  context.realtime_factor = 0;
  const auto refusal = [&](const std::vector<std::string>& command) -> std::string {
    try {
      internal::DilatedTimeEnvironment(image, context, command);
    } catch (const Error& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(refusal(sh).find("needs realtime pacing"), std::string::npos);
  context.realtime_factor = 2;
  // Debian's ldconfig is a static-pie program: a preloaded library never loads into it.
  if (access("/sbin/ldconfig", X_OK) == 0) {
    EXPECT_NE(refusal({"/sbin/ldconfig"}).find("/sbin/ldconfig is statically linked"),
              std::string::npos);
  }
}

// The companion of libfaketime: a socket timeout the program sets in its dilated seconds reaches
// the kernel in host seconds (divided by the factor), and reads back as the program set it. The
// module's own setsockopt/getsockopt are called (dlsym on its handle); the kernel's value is
// read with the raw system call, around both.
TEST(ImageTest, SocketTimeoutsAreScaledToHostTimeByTheFactor) {
  ASSERT_EQ(setenv("SITLNET_TIME_FACTOR", "2", 1), 0);
  void* module = dlopen(kSocketTimeoutsModule, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(module, nullptr) << dlerror();
  using Set = int (*)(int, int, int, const void*, socklen_t);
  using Get = int (*)(int, int, int, void*, socklen_t*);
  const auto shim_set = reinterpret_cast<Set>(dlsym(module, "setsockopt"));
  const auto shim_get = reinterpret_cast<Get>(dlsym(module, "getsockopt"));
  ASSERT_NE(shim_set, nullptr);
  ASSERT_NE(shim_get, nullptr);
  const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  ASSERT_GE(fd, 0);
  const auto kernel_us = [fd](int name) {
    timeval value{};
    socklen_t length = sizeof value;
    EXPECT_EQ(syscall(SYS_getsockopt, fd, SOL_SOCKET, name, &value, &length), 0);
    return int64_t{value.tv_sec} * 1000000 + value.tv_usec;
  };
  const auto set_us = [&](int name, int64_t us) {
    const timeval value{static_cast<time_t>(us / 1000000), static_cast<suseconds_t>(us % 1000000)};
    return shim_set(fd, SOL_SOCKET, name, &value, sizeof value);
  };
  ASSERT_EQ(set_us(SO_RCVTIMEO, 200000), 0);  // iputils ping -i 0.2
  EXPECT_EQ(kernel_us(SO_RCVTIMEO), 100000);  // 0.2 virtual s at 2 virtual s per host s
  timeval read_back{};
  socklen_t length = sizeof read_back;
  ASSERT_EQ(shim_get(fd, SOL_SOCKET, SO_RCVTIMEO, &read_back, &length), 0);
  EXPECT_EQ(read_back.tv_sec, 0);
  EXPECT_EQ(read_back.tv_usec, 200000);
  // (The kernel keeps timeouts in jiffies: these values are whole jiffies at HZ 100 to 1000.)
  ASSERT_EQ(set_us(SO_SNDTIMEO, 3000000), 0);
  EXPECT_EQ(kernel_us(SO_SNDTIMEO), 1500000);
  ASSERT_EQ(set_us(SO_RCVTIMEO, 1), 0);
  EXPECT_GT(kernel_us(SO_RCVTIMEO), 0);  // A timeout never becomes "none" (0).
  ASSERT_EQ(set_us(SO_RCVTIMEO, 0), 0);
  EXPECT_EQ(kernel_us(SO_RCVTIMEO), 0);  // "None" stays none.
  // Other options pass unchanged.
  const int buffer_bytes = 65536;
  ASSERT_EQ(shim_set(fd, SOL_SOCKET, SO_RCVBUF, &buffer_bytes, sizeof buffer_bytes), 0);
  int kernel_buffer_bytes = 0;
  socklen_t int_length = sizeof kernel_buffer_bytes;
  ASSERT_EQ(getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &kernel_buffer_bytes, &int_length), 0);
  EXPECT_EQ(kernel_buffer_bytes, 2 * buffer_bytes);  // socket(7): the kernel doubles it.
  close(fd);
  dlclose(module);
  unsetenv("SITLNET_TIME_FACTOR");
}

TEST(RobotProcessTest, ExitStatusIsReported) {
  // sitlnet exec is not built into this test; /bin/false stands in for a
  // sitlnet binary that fails at once, which is what a missing program does.
  const Image image = LoadImage(ImagesRoot(), "shell");
  const std::string log = ::testing::TempDir() + "/robot.log";
  std::remove(log.c_str());
  RobotProcess process(image, Context(), "/bin/false", log);
  const std::optional<int> status = process.WaitExit(10 * kNsPerS);
  ASSERT_TRUE(status);
  EXPECT_EQ(*status, 1);
}

TEST(RobotProcessTest, UnknownUserIsRejectedBeforeStarting) {
  Image image = LoadImage(ImagesRoot(), "shell");
  image.manifest.set_user("sitlnet-no-such-user");
  const std::string log = ::testing::TempDir() + "/robot-user.log";
  try {
    RobotProcess process(image, Context(), "/bin/false", log);
    FAIL() << "started with a user that does not exist";
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("\"sitlnet-no-such-user\" does not exist"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace sitlnet::images
