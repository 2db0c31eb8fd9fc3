// Image manifests (image.textproto) and placeholder expansion of their command and env.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "common/common.h"
#include "robot_images/robot_images.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // LoadImage reads a file: one per fuzzing process, rewritten for every input.
  static const std::string path =
      "/dev/shm/sitlnet-fuzz-image-" + std::to_string(getpid()) + ".textproto";
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) __builtin_trap();
  if (size > 0 && std::fwrite(data, 1, size, file) != size) __builtin_trap();
  std::fclose(file);
  static const bool cleanup = [] { return std::atexit([] { unlink(path.c_str()); }) == 0; }();
  (void)cleanup;
  try {
    const sitlnet::images::Image image = sitlnet::images::LoadImage("/nonexistent", path);
    sitlnet::images::LaunchContext context;
    context.sitlnet_bin_dir = "/bin";
    context.scenario = "fuzz";
    context.robot = "uav1";
    context.robot_index = 0;
    context.robot_args = {"--a", "b"};
    sitlnet::images::ExpandCommand(image, context);
    sitlnet::images::ExpandEnv(image, context);
  } catch (const sitlnet::Error&) {
  }
  return 0;
}
