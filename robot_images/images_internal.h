// Shared between the files of robot_images; not part of its public header.
#ifndef SITLNET_ROBOT_IMAGES_IMAGES_INTERNAL_H_
#define SITLNET_ROBOT_IMAGES_IMAGES_INTERNAL_H_

#include <sys/types.h>

#include <string>
#include <vector>

#include "robot_images/robot_images.h"

namespace sitlnet::images::internal {

// The descriptor on which bubblewrap writes its JSON info (--info-fd) in the robot's process.
constexpr int kSandboxInfoFd = 3;
// How long a robot's other processes may take to end once its command has (they are SIGKILLed).
constexpr TimeNs kSandboxEndTimeoutNs = 5 * kNsPerS;

// The "child-pid" of bubblewrap's JSON info read from `fd` (blocking until written or closed),
// or -1.
pid_t ReadSandboxInitPid(int fd);

// Where execvp finds `program`: itself if it holds a '/', else the first executable of that
// name on $PATH, or "" if there is none.
std::string FindProgram(const std::string& program);

// Expands every ${NAME} of `text`; throws Error naming the manifest for an unknown NAME.
std::string ExpandPlaceholders(const std::string& text, const Image& image,
                               const LaunchContext& context);

// Throws Error naming the robot, the path and the fix when the image's program (`command[0]`), a
// `files:` entry or a preload library lies where the image's sandbox does not show it (a
// private folder, a hidden path). Nothing to check for `sandbox: NONE` or a container image.
void CheckRobotSeesWhatItRuns(const Image& image, const LaunchContext& context,
                              const std::vector<std::string>& command);

// Throws Error "manifest: field: rule" for sandbox fields a robot must not have (a capability
// that reaches beyond the robot's namespaces, a relative path).
void CheckSandboxFields(const Image& image);

// The argv prefix that confines the image and switches its user (bubblewrap, then util-linux
// setpriv for `user`), to be followed by the image's own command. Empty when the image has
// neither a sandbox nor a user. `command_env` ("NAME=value") is set by bubblewrap for the
// command only. Throws Error naming the robot when a tool or privilege it needs is missing.
std::vector<std::string> ConfinementPrefix(const Image& image, const LaunchContext& context,
                                           const std::vector<std::string>& command_env = {});

// Whether the image's processes read the dilated clock (the manifest's `time`, by default when
// the run is realtime-paced at a factor other than 1).
bool UsesDilatedTime(const Image& image, const LaunchContext& context);

// sitlnet's own files that the image's processes load, bound read-only into its sandbox: the
// dilated-time preload libraries when the image reads the dilated clock; else none.
std::vector<std::string> SitlnetRuntimeFiles(const Image& image, const LaunchContext& context);

// Every library the image's command preloads: sitlnet's own (SitlnetRuntimeFiles) and those of
// the manifest's LD_PRELOAD (expanded; ':' or ' ' separated).
std::vector<std::string> PreloadLibraries(const Image& image, const LaunchContext& context);

// The environment that dilates the image's clock (libfaketime's LD_PRELOAD and FAKETIME), empty
// for WALL. Throws Error naming the robot for a statically linked `command[0]`, lockstep
// pacing, or a missing libfaketime; warns for a Go program.
std::vector<std::string> DilatedTimeEnvironment(const Image& image, const LaunchContext& context,
                                                const std::vector<std::string>& command);

// Throws Error "manifest: field: ..." for a manifest with neither command nor container_image,
// or a container image with fields that are for host programs (sandbox: NONE, hidden, time:
// DILATED).
void CheckContainerFields(const Image& image);

// `podman run ... IMAGE command...` for an image with container_image: in the robot's network
// namespace, every capability dropped but the manifest's, no_new_privs, the robot's SITLNET_*
// and the manifest's `env` (expanded, "NAME=value"), removed when it ends. Throws Error naming
// the robot when the run would dilate its clock.
std::vector<std::string> ContainerRunArgs(const Image& image, const LaunchContext& context,
                                          const ContainerTarget& target,
                                          const std::vector<std::string>& command,
                                          const std::vector<std::string>& env);

}  // namespace sitlnet::images::internal

#endif  // SITLNET_ROBOT_IMAGES_IMAGES_INTERNAL_H_
