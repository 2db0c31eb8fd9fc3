// A robot of a run and its image's process: what the setup starts, the supervisor watches and
// restarts, and the report stops and describes.
#ifndef SITLNET_RUNNER_ROBOT_SLOT_H_
#define SITLNET_RUNNER_ROBOT_SLOT_H_

#include <memory>
#include <optional>
#include <string>

#include "common/common.h"
#include "nns/nns.h"
#include "robot_images/robot_images.h"

namespace sitlnet::runner {

// A robot image's process and what became of it.
struct RobotSlot {
  std::string name;
  // A container image's registration for `down` (docs/containers.md); outlives `process`.
  std::unique_ptr<nns::ContainerRegistration> container;
  // The image's cgroup (host programs); outlives `process`. Null: none (no image, a container
  // image, or the host offers none).
  std::unique_ptr<nns::RobotCgroup> cgroup;
  std::optional<nns::CgroupUsage> usage;          // Read once its processes are gone.
  std::unique_ptr<images::RobotProcess> process;  // Null: no image.
  std::optional<int> exit_status;
  TimeNs exited_at_ns = 0;  // Virtual time the exit was noticed.
  // What it takes to start the image again (restart policy).
  images::Image image;
  images::LaunchContext context;
  std::string sitlnet_exe;
  uint32_t restarts = 0;
  TimeNs started_wall_ns = 0;  // For the readiness timeout.
  bool ready = false;
};

}  // namespace sitlnet::runner

#endif  // SITLNET_RUNNER_ROBOT_SLOT_H_
