// OCI container images as robot images: the `podman run` that starts one in the robot's network
// namespace (docs/containers.md).
#include <sys/resource.h>

#include <string>
#include <vector>

#include "robot_images/images_internal.h"
#include "robot_images/robot_images.h"
#include "scenario/scenario.h"

namespace sitlnet::images {
namespace {

// runc sets this process limit in every container here; the host's own (tens of thousands)
// was refused on this machine class (docs/containers.md).
constexpr int kContainerProcessLimit = 4096;

}  // namespace

std::optional<ContainerTarget> ContainerTargetOf(const Image& image, const LaunchContext& context) {
  if (image.manifest.container_image().empty()) return std::nullopt;
  ContainerTarget target;
  target.engine_exe = internal::FindProgram("podman");
  if (target.engine_exe.empty()) {
    throw Error("robot \"" + context.robot + "\": image \"" + image.manifest.name() +
                "\" is the container image \"" + image.manifest.container_image() + "\" (" +
                image.manifest_path +
                "), which needs podman (apt-get install podman runc catatonit)");
  }
  target.name = "sitlnet-" + RobotNetnsName(context.scenario, context.robot);
  return target;
}

namespace internal {

void CheckContainerFields(const Image& image) {
  const proto::ImageManifest& manifest = image.manifest;
  if (manifest.container_image().empty()) {
    if (manifest.command_size() == 0) {
      throw Error(image.manifest_path + ": image \"" + manifest.name() +
                  "\" has no command (and no container_image)");
    }
    return;
  }
  const auto refuse = [&](const std::string& field, const std::string& why) {
    throw Error(image.manifest_path + ": " + field + ": not for a container image (" + why + ")");
  };
  if (manifest.sandbox() == proto::ImageManifest::NONE) {
    refuse("sandbox: NONE", "the container engine confines it");
  }
  if (manifest.hidden_size() > 0) refuse("hidden", "the container sees its image's files only");
  if (manifest.time() == proto::ImageManifest::DILATED) {
    refuse("time: DILATED", "dilated time is for host programs, docs/time.md");
  }
  if (manifest.container_image()[0] == '-') {
    refuse("container_image \"" + manifest.container_image() + "\"", "not an image name");
  }
}

std::vector<std::string> ContainerRunArgs(const Image& image, const LaunchContext& context,
                                          const ContainerTarget& target,
                                          const std::vector<std::string>& command,
                                          const std::vector<std::string>& env) {
  const proto::ImageManifest& manifest = image.manifest;
  if (UsesDilatedTime(image, context)) {
    throw Error("robot \"" + context.robot + "\": image \"" + manifest.name() +
                "\" is a container image, whose clock sitlnet cannot dilate (realtime factor " +
                std::to_string(context.realtime_factor) +
                "): run at factor 1, in lockstep, or "
                "set `time: WALL` in " +
                image.manifest_path + " to keep the host's clock");
  }
  // The engine's default open-file limit may be above the host's hard one, which the kernel
  // refuses: the container gets the run's own.
  rlimit files{};
  getrlimit(RLIMIT_NOFILE, &files);
  const std::string nofile =
      std::to_string(files.rlim_max == RLIM_INFINITY ? 1048576 : files.rlim_max);
  std::vector<std::string> args = {
      // From the root namespace: runc refuses the network sysctls podman sets by default in a
      // namespace it would share with its caller.
      target.engine_exe, "run", "--rm",
      // A container of this name left by a run that was killed is replaced, not refused.
      "--replace", "--name", target.name,
      // Never downloaded: the image is already on this host, or the robot fails at start.
      "--pull", "never", "--network",
      "ns:/run/netns/" + RobotNetnsName(context.scenario, context.robot), "--hostname",
      context.robot,
      // An init as PID 1 forwards SIGTERM to the command and reaps its children.
      "--init", "--cap-drop", "ALL", "--security-opt", "no-new-privileges", "--ulimit",
      "nofile=" + nofile + ":" + nofile, "--ulimit",
      "nproc=" + std::to_string(kContainerProcessLimit) + ":" +
          std::to_string(kContainerProcessLimit),
      "--label", "io.sitlnet.scenario=" + context.scenario, "--label",
      "io.sitlnet.robot=" + context.robot};
  for (const std::string& capability : manifest.capabilities()) {
    args.insert(args.end(), {"--cap-add", capability});
  }
  // The robot's place, as `sitlnet exec` tells a host program (docs/robot-images.md).
  for (const std::string& variable :
       {"SITLNET_SCENARIO=" + context.scenario, "SITLNET_ROBOT=" + context.robot,
        "SITLNET_ROBOT_INDEX=" + std::to_string(context.robot_index)}) {
    args.insert(args.end(), {"--env", variable});
  }
  if (!context.physics_address.empty()) {
    args.insert(args.end(), {"--env", "SITLNET_PHYSICS_ADDR=" + context.physics_address});
  }
  for (const std::string& variable : env) args.insert(args.end(), {"--env", variable});
  if (!manifest.user().empty()) args.insert(args.end(), {"--user", manifest.user()});
  for (const std::string& path : manifest.writable()) {
    const std::string host_path = ExpandPlaceholders(path, image, context);
    args.insert(args.end(), {"--volume", host_path + ":" + host_path});
  }
  args.push_back(manifest.container_image());
  args.insert(args.end(), command.begin(), command.end());
  return args;
}

}  // namespace internal
}  // namespace sitlnet::images
