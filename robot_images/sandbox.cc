// The robot sandbox: how an image's command is wrapped in bubblewrap (and util-linux setpriv
// for `user`) so that it reaches nothing of the host but its own network namespace
// (docs/security.md, "The robot sandbox").
#include <linux/capability.h>
#include <pwd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string_view>

#include "robot_images/images_internal.h"

namespace sitlnet::images::internal {
namespace {

// Capabilities an image may keep: each acts only on the robot's own namespaces (its network
// namespace, its PID namespace) or on its own scheduling. Anything that reaches the host's
// files, devices, kernel or other namespaces (CAP_SYS_ADMIN, CAP_DAC_OVERRIDE, CAP_SYS_PTRACE,
// CAP_SYS_MODULE, ...) is refused: an image that needs one runs with `sandbox: NONE`.
constexpr std::array<std::string_view, 9> kAllowedCapabilities = {
    "CAP_NET_ADMIN", "CAP_NET_RAW", "CAP_NET_BIND_SERVICE", "CAP_NET_BROADCAST", "CAP_IPC_LOCK",
    "CAP_KILL",      "CAP_SETUID",  "CAP_SETGID",           "CAP_SYS_NICE"};

// What the OCI runtimes hide from or make read-only in a container's /proc and /sys (the
// masked and read-only paths of Moby's default container spec, docs/references.md#sandbox): kernel
// memory, keyrings, timer and scheduler internals, and the knobs that act on the whole host
// (sysctl, sysrq, IRQ affinity). A root process without capabilities may still write a file
// that root owns, so these must not be writable. Only the paths that exist are touched.
constexpr std::array<std::string_view, 11> kMaskedPaths = {"/proc/acpi",
                                                           "/proc/asound",
                                                           "/proc/kcore",
                                                           "/proc/keys",
                                                           "/proc/latency_stats",
                                                           "/proc/timer_list",
                                                           "/proc/timer_stats",
                                                           "/proc/sched_debug",
                                                           "/proc/scsi",
                                                           "/sys/firmware",
                                                           "/sys/devices/virtual/powercap"};
constexpr std::array<std::string_view, 5> kReadOnlyProcPaths = {
    "/proc/bus", "/proc/fs", "/proc/irq", "/proc/sys", "/proc/sysrq-trigger"};

bool Exists(const std::string& path, bool* is_dir = nullptr) {
  struct stat info {};
  if (lstat(path.c_str(), &info) != 0) return false;
  if (is_dir != nullptr) *is_dir = S_ISDIR(info.st_mode);
  return true;
}

// "CAP_NET_RAW" -> "net_raw", setpriv's spelling.
std::string SetprivCapabilityName(const std::string& name) {
  std::string out = name.substr(4);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return out;
}

// A path the sandbox hides: an empty folder in place of a folder, /dev/null in place of a file.
void Hide(const std::string& path, std::vector<std::string>* args) {
  bool is_dir = false;
  if (!Exists(path, &is_dir)) return;
  if (is_dir) {
    args->insert(args->end(), {"--tmpfs", path, "--remount-ro", path});
  } else {
    args->insert(args->end(), {"--ro-bind", "/dev/null", path});
  }
}

// The folders the sandbox replaces with empty ones of its own; everything else of the host is
// there, read-only, through `--ro-bind / /`.
constexpr std::array<std::string_view, 3> kPrivateFolders = {"/run", "/tmp", "/var/tmp"};

bool IsWithin(const std::string& path, std::string_view folder) {
  return path.size() > folder.size() && path.compare(0, folder.size(), folder) == 0 &&
         path[folder.size()] == '/';
}

bool IsInPrivateFolder(const std::string& path) {
  return std::any_of(kPrivateFolders.begin(), kPrivateFolders.end(),
                     [&](std::string_view folder) { return IsWithin(path, folder); });
}

// Binds host `path` at the same place (`how`: --bind or --ro-bind). bubblewrap creates the
// missing parents of the target (in the private /tmp, say) with mode 0700, which a robot's
// `user` could not cross: each parent inside a private folder gets its host mode instead
// (parents elsewhere exist already).
void Bind(const char* how, const std::string& path, std::vector<std::string>* args) {
  for (size_t slash = path.find('/', 1); slash != std::string::npos;
       slash = path.find('/', slash + 1)) {
    const std::string parent = path.substr(0, slash);
    if (!IsInPrivateFolder(parent)) continue;
    struct stat info {};
    if (stat(parent.c_str(), &info) != 0) continue;
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", info.st_mode & 07777);
    args->insert(args->end(), {"--perms", mode, "--dir", parent});
  }
  args->insert(args->end(), {how, path, path});
}

std::vector<std::string> BubblewrapArgs(const Image& image, const LaunchContext& context,
                                        const passwd* user,
                                        const std::vector<std::string>& command_env) {
  const proto::ImageManifest& manifest = image.manifest;
  // --die-with-parent: the sandbox ends with `sitlnet run`, even when it is killed. The PID
  // namespace ends every process of the robot with its first one, also those that forked away
  // or changed their other namespaces (they cannot leave this one without CAP_SYS_ADMIN).
  std::vector<std::string> args = {
      "bwrap", "--die-with-parent", "--info-fd", std::to_string(kSandboxInfoFd), "--new-session",
      "--unshare-pid", "--unshare-ipc", "--unshare-uts", "--unshare-cgroup-try", "--hostname",
      context.robot, "--ro-bind", "/", "/", "--dev", "/dev", "--proc", "/proc",
      // /run holds /run/sitlnet (state files, control sockets) and
      // /run/netns (every robot's namespace).
      "--tmpfs", "/run", "--tmpfs", "/tmp", "--tmpfs", "/var/tmp"};
  for (std::string_view path : kMaskedPaths) Hide(std::string(path), &args);
  for (std::string_view path : kReadOnlyProcPaths) {
    const std::string host_path(path);
    if (Exists(host_path)) args.insert(args.end(), {"--ro-bind", host_path, host_path});
  }
  // The image's own files stay visible where they are, also in a private folder (/tmp): bound
  // in only there, read-only, and a file only when its folder is not bound already; writable
  // paths read-write. bubblewrap mounts in order, a later mount over an earlier one: parents
  // first, so that a writable folder inside the image's folder stays writable and an image
  // folder inside a writable one stays read-only.
  std::vector<std::pair<const char*, std::string>> binds;
  const std::string image_dir = std::filesystem::absolute(image.dir).lexically_normal().string();
  if (IsInPrivateFolder(image_dir)) binds.emplace_back("--ro-bind", image_dir);
  for (const std::string& file : manifest.files()) {
    const std::string path = ExpandPlaceholders(file, image, context);
    if (IsInPrivateFolder(path) && !IsWithin(path, image_dir)) {
      binds.emplace_back("--ro-bind", std::filesystem::path(path).lexically_normal().string());
    }
  }
  // sitlnet's own files that the image's processes load (the dilated-time preload libraries),
  // wherever sitlnet was built: a checkout under /tmp too.
  for (const std::string& path : SitlnetRuntimeFiles(image, context)) {
    if (IsInPrivateFolder(path) && !IsWithin(path, image_dir)) binds.emplace_back("--ro-bind", path);
  }
  for (const std::string& path : manifest.writable()) {
    const std::string host_path = ExpandPlaceholders(path, image, context);
    if (!Exists(host_path)) {
      throw Error("robot \"" + context.robot + "\": image \"" + manifest.name() +
                  "\" writable path " + host_path + " does not exist (" + image.manifest_path +
                  ")");
    }
    binds.emplace_back("--bind", std::filesystem::path(host_path).lexically_normal().string());
  }
  std::stable_sort(binds.begin(), binds.end(), [](const auto& a, const auto& b) {
    return std::count(a.second.begin(), a.second.end(), '/') <
           std::count(b.second.begin(), b.second.end(), '/');
  });
  for (const auto& [how, path] : binds) Bind(how, path, &args);
  for (const std::string& path : manifest.hidden()) {
    Hide(ExpandPlaceholders(path, image, context), &args);
  }
  args.insert(args.end(), {"--cap-drop", "ALL"});
  for (const std::string& capability : manifest.capabilities()) {
    args.insert(args.end(), {"--cap-add", capability});
  }
  if (user != nullptr) {
    // setpriv, inside the sandbox, needs these two to switch user; it loses them in the switch.
    args.insert(args.end(), {"--cap-add", "CAP_SETUID", "--cap-add", "CAP_SETGID"});
    args.insert(args.end(), {"--setenv", "HOME", user->pw_dir, "--setenv", "USER", user->pw_name,
                             "--setenv", "LOGNAME", user->pw_name});
  }
  for (const std::string& variable : command_env) {
    const size_t equals = variable.find('=');
    args.insert(args.end(), {"--setenv", variable.substr(0, equals), variable.substr(equals + 1)});
  }
  args.push_back("--");
  return args;
}

// util-linux setpriv drops to the user, unmodified. The group is the user's primary group by
// number: Debian's "nobody" has group "nogroup", so --regid=<user name> fails there. The
// environment is kept (the SITLNET_* variables and the manifest's env); capabilities the
// manifest names survive the switch as ambient capabilities.
std::vector<std::string> SetprivArgs(const Image& image, const passwd& user) {
  std::vector<std::string> args = {"setpriv", "--init-groups",
                                   "--reuid=" + std::to_string(user.pw_uid),
                                   "--regid=" + std::to_string(user.pw_gid)};
  if (image.manifest.capabilities_size() > 0) {
    std::string caps;
    for (const std::string& capability : image.manifest.capabilities()) {
      caps += ",+" + SetprivCapabilityName(capability);
    }
    args.push_back("--inh-caps=-all" + caps);
    args.push_back("--ambient-caps=-all" + caps);
  }
  args.push_back("--");
  return args;
}

std::string Normal(const std::string& path) {
  return std::filesystem::absolute(path).lexically_normal().string();
}

bool IsAtOrWithin(const std::string& path, const std::string& folder) {
  return path == folder || IsWithin(path, folder);
}

// Why the sandbox of `image` does not show host `path` to the robot ("it lies in ..., which
// ..."), or "" when it does. Mirrors BubblewrapArgs: hidden paths win; a private folder shows
// only the image's folder, its `files`, its `writable` paths and sitlnet's runtime files.
std::string WhyRobotCannotSee(const Image& image, const LaunchContext& context,
                              const std::string& host_path) {
  const std::string path = Normal(host_path);
  for (const std::string& hidden : image.manifest.hidden()) {
    const std::string folder = Normal(ExpandPlaceholders(hidden, image, context));
    if (IsAtOrWithin(path, folder)) {
      return "it lies in " + folder + ", which the manifest hides (hidden:): remove it there";
    }
  }
  const auto private_folder =
      std::find_if(kPrivateFolders.begin(), kPrivateFolders.end(),
                   [&](std::string_view folder) { return IsWithin(path, folder); });
  if (private_folder == kPrivateFolders.end()) return "";
  std::vector<std::string> shown = {Normal(image.dir)};
  for (const auto* field : {&image.manifest.files(), &image.manifest.writable()}) {
    for (const std::string& entry : *field) {
      shown.push_back(Normal(ExpandPlaceholders(entry, image, context)));
    }
  }
  for (const std::string& file : SitlnetRuntimeFiles(image, context)) shown.push_back(file);
  if (std::any_of(shown.begin(), shown.end(),
                  [&](const std::string& folder) { return IsAtOrWithin(path, folder); })) {
    return "";
  }
  return "it lies in " + std::string(*private_folder) +
         ", which the robot's sandbox keeps private and empty: list it or its folder in the "
         "manifest's files:, or move it out of /run, /tmp and /var/tmp";
}

}  // namespace

void CheckRobotSeesWhatItRuns(const Image& image, const LaunchContext& context,
                              const std::vector<std::string>& command) {
  if (image.manifest.sandbox() != proto::ImageManifest::CONFINED ||
      !image.manifest.container_image().empty()) {
    return;  // The host's files as they are, or the container's own.
  }
  const auto check = [&](const std::string& what, const std::string& path) {
    if (path.empty() || path[0] != '/') return;
    const std::string why = WhyRobotCannotSee(image, context, path);
    if (!why.empty()) {
      throw Error("robot \"" + context.robot + "\": image \"" + image.manifest.name() + "\" (" +
                  image.manifest_path + "): " + what + " " + path + " is not visible to it: " + why);
    }
  };
  if (!command.empty()) check("its program", FindProgram(command[0]));
  for (const std::string& file : image.manifest.files()) {
    check("files: entry", ExpandPlaceholders(file, image, context));
  }
  // A library the robot's loader cannot open is skipped with a line in its log: the run would go
  // on without it (undilated, for sitlnet's own).
  for (const std::string& library : PreloadLibraries(image, context)) {
    check("preload library", library);
  }
}

std::string FindProgram(const std::string& program) {
  if (program.find('/') != std::string::npos) return program;
  const char* path = std::getenv("PATH");
  std::string_view rest = path != nullptr ? path : "/usr/bin:/bin";
  while (true) {
    const size_t colon = rest.find(':');
    const std::string dir(rest.substr(0, colon));
    if (!dir.empty() && access((dir + "/" + program).c_str(), X_OK) == 0) {
      return dir + "/" + program;
    }
    if (colon == std::string_view::npos) return "";
    rest.remove_prefix(colon + 1);
  }
}

pid_t ReadSandboxInitPid(int fd) {
  std::string json;
  char buffer[256];
  for (ssize_t n; (n = read(fd, buffer, sizeof buffer)) != 0;) {
    if (n < 0) {
      if (errno == EINTR) continue;
      return -1;
    }
    json.append(buffer, static_cast<size_t>(n));
    if (json.find('}') != std::string::npos) break;
  }
  // {"child-pid": 1234, ...}: bubblewrap's documented --info-fd output.
  const size_t key = json.find("\"child-pid\"");
  if (key == std::string::npos) return -1;
  const size_t colon = json.find(':', key);
  if (colon == std::string::npos) return -1;
  return static_cast<pid_t>(std::strtol(json.c_str() + colon + 1, nullptr, 10));
}

void CheckSandboxFields(const Image& image) {
  const proto::ImageManifest& manifest = image.manifest;
  for (const std::string& capability : manifest.capabilities()) {
    if (std::find(kAllowedCapabilities.begin(), kAllowedCapabilities.end(), capability) ==
        kAllowedCapabilities.end()) {
      std::string allowed;
      for (std::string_view name : kAllowedCapabilities) allowed += " " + std::string(name);
      throw Error(image.manifest_path + ": capabilities: \"" + capability +
                  "\" is not one a sandboxed robot may keep (allowed:" + allowed +
                  "); an image that needs more runs with `sandbox: NONE`");
    }
  }
  if (manifest.sandbox() == proto::ImageManifest::NONE && manifest.capabilities_size() > 0 &&
      manifest.user().empty()) {
    throw Error(image.manifest_path +
                ": capabilities: only a sandboxed image or one with `user` can be limited to "
                "named capabilities (`sandbox: NONE` without `user` keeps the caller's)");
  }
  for (const auto* field : {&manifest.writable(), &manifest.hidden()}) {
    for (const std::string& path : *field) {
      if (path.empty() || (path[0] != '/' && path[0] != '$')) {
        throw Error(image.manifest_path + ": " +
                    (field == &manifest.writable() ? "writable" : "hidden") + ": \"" + path +
                    "\" is not an absolute path");
      }
    }
  }
  if (manifest.sandbox() == proto::ImageManifest::NONE &&
      (manifest.writable_size() > 0 || manifest.hidden_size() > 0)) {
    throw Error(image.manifest_path +
                ": writable and hidden need the sandbox (the image has `sandbox: NONE`)");
  }
}

std::vector<std::string> ConfinementPrefix(const Image& image, const LaunchContext& context,
                                           const std::vector<std::string>& command_env) {
  const proto::ImageManifest& manifest = image.manifest;
  const passwd* user = nullptr;
  if (!manifest.user().empty()) {
    user = getpwnam(manifest.user().c_str());
    if (user == nullptr) {
      throw Error("robot \"" + context.robot + "\": image user \"" + manifest.user() +
                  "\" does not exist on this host (" + image.manifest_path + ")");
    }
    // Checked here rather than left to setpriv, whose "setresuid failed" would only reach the
    // robot's log (docs/security.md: a run under only CAP_NET_ADMIN + CAP_SYS_ADMIN).
    if (!HasEffectiveCapability(CAP_SETUID) || !HasEffectiveCapability(CAP_SETGID)) {
      throw Error("robot \"" + context.robot + "\": image user \"" + manifest.user() + "\" (" +
                  image.manifest_path +
                  ") needs CAP_SETUID and CAP_SETGID to switch user: run as root, or remove "
                  "`user` from the manifest");
    }
  }
  std::vector<std::string> prefix;
  if (manifest.sandbox() == proto::ImageManifest::CONFINED) {
    if (FindProgram("bwrap").empty()) {
      throw Error("robot \"" + context.robot + "\": image \"" + manifest.name() +
                  "\" runs in a sandbox, which needs bubblewrap (apt-get install bubblewrap; "
                  "or `sandbox: NONE` in " +
                  image.manifest_path + ")");
    }
    prefix = BubblewrapArgs(image, context, user, command_env);
  }
  if (user != nullptr) {
    const std::vector<std::string> setpriv = SetprivArgs(image, *user);
    prefix.insert(prefix.end(), setpriv.begin(), setpriv.end());
  }
  return prefix;
}

}  // namespace sitlnet::images::internal
