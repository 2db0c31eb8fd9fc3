#include "robot_images/robot_images.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>

namespace sitlnet::images {
namespace {

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

TEST(ImageTest, ShippedImagesLoad) {
  for (const char* name : {"flocker", "iperf", "shell"}) {
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
