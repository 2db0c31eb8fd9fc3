// Image manifests: loading, validation and placeholder expansion.
#include <sys/stat.h>

#include <cmath>
#include <cstdlib>
#include <string_view>

#include "robot_images/images_internal.h"
#include "robot_images/robot_images.h"
#include "scenario/scenario.h"

namespace sitlnet::images {
namespace {

bool IsFile(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

bool Exists(const std::string& path) {
  struct stat info {};
  return stat(path.c_str(), &info) == 0;
}

constexpr std::string_view kEnvPrefix = "env:";

}  // namespace

namespace internal {

std::string ExpandPlaceholders(const std::string& text, const Image& image,
                               const LaunchContext& context) {
  std::string out;
  size_t i = 0;
  while (i < text.size()) {
    const size_t open = text.find("${", i);
    if (open == std::string::npos) {
      out += text.substr(i);
      break;
    }
    out += text.substr(i, open - i);
    const size_t close = text.find('}', open);
    if (close == std::string::npos) {
      throw Error(image.manifest_path + ": unterminated placeholder in \"" + text + "\"");
    }
    const std::string name = text.substr(open + 2, close - open - 2);
    if (name == "IMAGE_DIR") {
      out += image.dir;
    } else if (name == "SITLNET_BIN") {
      out += context.sitlnet_bin_dir;
    } else if (name == "ROBOT") {
      out += context.robot;
    } else if (name == "ROBOT_INDEX") {
      out += std::to_string(context.robot_index);
    } else if (name == "SCENARIO") {
      out += context.scenario;
    } else if (name == "AIRFRAME") {
      out += context.airframe_text;
    } else if (name == "GEODETIC_ORIGIN") {
      out += context.geodetic_origin;
    } else if (name.rfind(kEnvPrefix, 0) == 0) {
      // The caller's environment, for what differs between hosts (where an autopilot is built).
      const std::string variable = name.substr(kEnvPrefix.size());
      const char* value = variable.empty() ? nullptr : std::getenv(variable.c_str());
      if (value == nullptr || *value == '\0') {
        throw Error(image.manifest_path + ": ${" + name + "}: " +
                    (variable.empty() ? std::string("names no variable")
                                      : variable + " is not set in sitlnet's environment (the "
                                                   "manifest's comments say what it names)"));
      }
      out += value;
    } else {
      throw Error(
          image.manifest_path + ": unknown placeholder ${" + name + "} in \"" + text +
          "\" (known: IMAGE_DIR SITLNET_BIN ROBOT ROBOT_INDEX SCENARIO AIRFRAME GEODETIC_ORIGIN "
          "env:NAME, and ${ARGS} as a whole command element)");
    }
    i = close + 1;
  }
  return out;
}

}  // namespace internal

using internal::ExpandPlaceholders;

namespace {

// Throws Error "manifest: limits.field: rule" for a limit that no cgroup could hold.
void CheckLimits(const Image& image) {
  if (!image.manifest.has_limits()) return;
  const proto::ImageManifest::Limits& limits = image.manifest.limits();
  const auto refuse = [&](const std::string& field, const std::string& rule) {
    throw Error(image.manifest_path + ": limits." + field + ": " + rule);
  };
  if (!image.manifest.container_image().empty()) {
    refuse("*", "for host programs; a container image is limited by its engine");
  }
  if (!std::isfinite(limits.cpu_max_cores()) || limits.cpu_max_cores() < 0 ||
      limits.cpu_max_cores() > 1024) {
    refuse("cpu_max_cores", "must be a number of cores from 0 (no limit) to 1024");
  }
  if (limits.has_cpu_max_cores() && limits.cpu_max_cores() > 0 && limits.cpu_max_cores() < 0.01) {
    refuse("cpu_max_cores", "must be at least 0.01 (1 ms of CPU time per 100 ms)");
  }
  if (limits.memory_max_mib() > 1024 * 1024) refuse("memory_max_mib", "must be at most 1 TiB");
  // The kernel's own ceiling (PID_MAX_LIMIT on 64-bit): pids.max refuses more.
  if (limits.pids_max() > 4 * 1024 * 1024) refuse("pids_max", "must be at most 4194304");
}

}  // namespace

Image LoadImage(const std::string& images_root, const std::string& name) {
  Image image;
  image.manifest_path = IsFile(name) ? name : images_root + "/" + name + "/image.textproto";
  if (!IsFile(image.manifest_path)) {
    throw Error("image \"" + name + "\": no manifest at " + image.manifest_path);
  }
  const size_t slash = image.manifest_path.rfind('/');
  image.dir = slash == std::string::npos ? "." : image.manifest_path.substr(0, slash);
  ParseTextProtoOrThrow(ReadFileOrThrow(image.manifest_path, "image manifest"), image.manifest_path,
                        &image.manifest);
  for (const auto& env : image.manifest.env()) {
    if (env.name().empty() || env.name().find('=') != std::string::npos) {
      throw Error(image.manifest_path + ": env name \"" + env.name() + "\" is not valid");
    }
  }
  internal::CheckContainerFields(image);
  internal::CheckSandboxFields(image);
  CheckLimits(image);
  // A day: far above any boot, far from int64's end once summed over a fleet.
  if (image.manifest.boot_cost_ms() < 0 || image.manifest.boot_cost_ms() > 86400000) {
    throw Error(image.manifest_path + ": boot_cost_ms: must be from 0 to 86400000 (a day)");
  }
  return image;
}

std::vector<std::string> ExpandCommand(const Image& image, const LaunchContext& context) {
  std::vector<std::string> argv;
  for (const std::string& element : image.manifest.command()) {
    if (element == "${ARGS}") {
      argv.insert(argv.end(), context.robot_args.begin(), context.robot_args.end());
    } else {
      argv.push_back(ExpandPlaceholders(element, image, context));
    }
  }
  return argv;
}

std::vector<std::string> ExpandEnv(const Image& image, const LaunchContext& context) {
  std::vector<std::string> env;
  for (const auto& variable : image.manifest.env()) {
    env.push_back(variable.name() + "=" + ExpandPlaceholders(variable.value(), image, context));
  }
  return env;
}

void CheckFiles(const Image& image, const LaunchContext& context) {
  for (const std::string& file : image.manifest.files()) {
    const std::string path = ExpandPlaceholders(file, image, context);
    if (!Exists(path)) {
      throw Error("robot \"" + context.robot + "\": image \"" + image.manifest.name() +
                  "\" needs " + path + ", which does not exist");
    }
  }
  internal::CheckRobotSeesWhatItRuns(image, context, ExpandCommand(image, context));
}

}  // namespace sitlnet::images
