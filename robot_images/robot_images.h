// sitlnet robot_images: image manifests (what onboard software to run in a
// robot and how) and the supervision of the processes that run them. An image
// runs exactly as `sitlnet exec` runs a program. docs/robot-images.md.
#ifndef SITLNET_ROBOT_IMAGES_ROBOT_IMAGES_H_
#define SITLNET_ROBOT_IMAGES_ROBOT_IMAGES_H_

#include <sys/types.h>

#include <optional>
#include <string>
#include <vector>

#include "common/common.h"
#include "sitlnet/image.pb.h"

namespace sitlnet::images {

//-------------------------------- Manifests ---------------------------------

struct Image {
  proto::ImageManifest manifest;
  std::string manifest_path;
  std::string dir;  // Folder of the manifest (${IMAGE_DIR}).
};

// Loads `<images_root>/<name>/image.textproto`, or `name` itself when it is a
// path to a manifest file. Throws Error "path:line:col: rule" on bad input.
Image LoadImage(const std::string& images_root, const std::string& name);

// What placeholders expand to for one robot.
struct LaunchContext {
  std::string sitlnet_bin_dir;  // ${SITLNET_BIN}
  std::string scenario;         // ${SCENARIO}
  std::string robot;            // ${ROBOT}
  int robot_index = 0;          // ${ROBOT_INDEX}
  // "a.b.c.d:port" of the robot's physics server (SITLNET_PHYSICS_ADDR of a container image,
  // which is not started through `sitlnet exec`); empty: none is given.
  std::string physics_address;
  std::vector<std::string> robot_args;  // "${ARGS}"
  std::string airframe_text;            // ${AIRFRAME}: the robot's Airframe, text format
  // ${GEODETIC_ORIGIN}: the scenario's geodetic_origin as "latitude_deg,longitude_deg,altitude_m"
  // (ArduPilot's --home, without its heading).
  std::string geodetic_origin;
  // Virtual seconds per wall second of a realtime-paced run; 0 in lockstep (no fixed factor).
  double realtime_factor = 1.0;
  // A descriptor of the run that the command receives as kPassedFd (the shared virtual time of
  // the /clock publisher); -1: none. Every other descriptor of the run stays out.
  int passed_fd = -1;
  // cgroup.procs files (open for writing) the robot's process joins before it runs anything, so
  // that all its processes are in the robot's cgroup (nns::RobotCgroup); none: no cgroup.
  std::vector<int> cgroup_join_fds;
  // Who starts the robot, as its warnings begin: "sitlnet run", or "sitlnet node" on a node host.
  std::string program = "sitlnet run";
};
inline constexpr int kPassedFd = 4;

// The image's argv with placeholders expanded; throws Error naming the
// manifest and the unknown placeholder.
std::vector<std::string> ExpandCommand(const Image& image, const LaunchContext& context);
// "NAME=value" pairs of the manifest's env, expanded.
std::vector<std::string> ExpandEnv(const Image& image, const LaunchContext& context);
// Throws Error "robot "r": image "x" needs file F, which does not exist".
void CheckFiles(const Image& image, const LaunchContext& context);

// An image that names an OCI container image (the manifest's `container_image`): the engine
// that runs it and the container's name, "sitlnet-<robot's namespace>" (docs/containers.md).
struct ContainerTarget {
  std::string engine_exe;  // podman's path
  std::string name;
};
// nullopt for a host program; throws Error naming the robot when podman is not installed.
std::optional<ContainerTarget> ContainerTargetOf(const Image& image, const LaunchContext& context);

//------------------------------- Processes ----------------------------------

// One robot's running image: `sitlnet exec --scenario S ROBOT -- [bwrap ... --] [setpriv ...
// --] argv...` with stdout and stderr appended to `log_path`: in the robot's network namespace,
// confined by the manifest's sandbox (docs/security.md). A container image is `podman run ...
// --network ns:<robot's namespace> IMAGE [command...]` instead, attached: podman forwards
// signals to the container and removes it when it ends. Not copyable.
class RobotProcess {
 public:
  // Starts the process; throws Error naming the robot on failure to fork.
  RobotProcess(const Image& image, const LaunchContext& context, const std::string& sitlnet_exe,
               const std::string& log_path);
  ~RobotProcess();  // Stops the process if still running.
  RobotProcess(const RobotProcess&) = delete;
  RobotProcess& operator=(const RobotProcess&) = delete;

  pid_t pid() const { return pid_; }
  const std::string& robot() const { return robot_; }
  const std::string& log_path() const { return log_path_; }

  // Non-blocking: the exit status (as a shell shows it: 128+N for signal N)
  // if the process has ended, else nullopt. Under the sandbox the robot's other processes may
  // still be ending then; WaitExit and Stop wait for them too.
  std::optional<int> PollExit();

  // Waits up to `timeout_ns` for the process, and under the sandbox every process of the
  // robot, to end; its status, or nullopt.
  std::optional<int> WaitExit(TimeNs timeout_ns);

  // A descriptor that becomes readable (POLLIN) when the process ends, for a caller's poll; -1
  // when there is none (then PollExit must be called now and then).
  int exit_fd() const { return pidfd_; }

  // True once the manifest's ready_log_line is in the log (or there is none).
  bool IsReady() const;

  // SIGTERM to the image's command, then SIGKILL after `grace_ns` (to the sandbox, which ends
  // every process of the robot); waits for the exit. Idempotent.
  void Stop(TimeNs grace_ns = 2 * kNsPerS);

  // SIGTERM to the image's command without waiting (Stop() later), to stop many at once.
  void RequestStop();

  // The image's command: pid() itself without a sandbox, else the command bubblewrap started
  // (pid() is bubblewrap's, which forwards no signal). pid() if it cannot be found (yet).
  pid_t CommandPid();

 private:
  pid_t SandboxInit();
  void Terminate();  // SIGTERM to the command, or KillSandbox() if it has not started.
  // SIGKILL to the sandbox's init (its whole PID namespace), or the container removed by force;
  // and SIGKILL to pid().
  void KillSandbox();
  void WaitSandboxGone(TimeNs timeout_ns);

  std::string robot_;
  std::string log_path_;
  std::string ready_line_;
  bool sandboxed_ = false;
  pid_t pid_ = -1;
  int pidfd_ = -1;
  int info_fd_ = -1;     // bubblewrap's --info-fd, until read.
  pid_t init_pid_ = -1;  // The sandbox's init (PID 1 inside), in our PID namespace.
  int init_pidfd_ = -1;
  std::optional<int> exit_status_;
  std::optional<ContainerTarget> container_;
};

}  // namespace sitlnet::images

#endif  // SITLNET_ROBOT_IMAGES_ROBOT_IMAGES_H_
