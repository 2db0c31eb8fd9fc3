// Dilated time: an image's processes read a clock that runs at the run's realtime factor,
// through Debian's libfaketime (LD_PRELOAD), so unmodified wall-clock programs (ping, iperf3,
// babeld) keep their intervals and timeouts in virtual time (docs/time.md).
#include <elf.h>
#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string_view>

#include "robot_images/images_internal.h"

namespace sitlnet::images::internal {
namespace {

// libfaketime's thread-safe build (iperf3 and DDS programs are multi-threaded).
constexpr const char* kLibfaketime = SITLNET_LIBFAKETIME_PATH;
// Scales the socket timeouts libfaketime leaves alone (socket_timeouts/).
constexpr const char* kSocketTimeouts = SITLNET_SOCKET_TIMEOUTS_PATH;

enum class Linkage { kDynamic, kStatic, kGo, kUnknown };

// From the ELF file itself: a program without an interpreter (PT_INTERP) is static, and
// libfaketime, a preloaded library, never loads into it; a Go program reads its clock through
// the vDSO or raw system calls, around libc, whatever its linkage.
Linkage LinkageOf(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return Linkage::kUnknown;
  Elf64_Ehdr header{};
  Linkage linkage = Linkage::kUnknown;
  if (pread(fd, &header, sizeof header, 0) == sizeof header &&
      std::memcmp(header.e_ident, ELFMAG, SELFMAG) == 0 && header.e_ident[EI_CLASS] == ELFCLASS64) {
    linkage = Linkage::kStatic;
    for (int i = 0; i < header.e_phnum; ++i) {
      Elf64_Phdr program_header{};
      const off_t at = static_cast<off_t>(header.e_phoff) + i * header.e_phentsize;
      if (pread(fd, &program_header, sizeof program_header, at) != sizeof program_header) break;
      if (program_header.p_type == PT_INTERP) linkage = Linkage::kDynamic;
    }
    // Go's linker writes a section named .note.go.buildid into every binary.
    Elf64_Shdr names{};
    const off_t names_at =
        static_cast<off_t>(header.e_shoff) + header.e_shstrndx * header.e_shentsize;
    if (header.e_shoff != 0 && pread(fd, &names, sizeof names, names_at) == sizeof names) {
      std::string table(names.sh_size, '\0');
      if (names.sh_size < (1 << 20) &&
          pread(fd, table.data(), table.size(), static_cast<off_t>(names.sh_offset)) ==
              static_cast<ssize_t>(table.size()) &&
          table.find(std::string_view(".note.go.buildid\0", 17)) != std::string::npos) {
        linkage = Linkage::kGo;
      }
    }
  } else if (pread(fd, &header, 2, 0) == 2 && std::memcmp(&header, "#!", 2) == 0) {
    linkage = Linkage::kDynamic;  // A script: its interpreter is a dynamically linked program.
  }
  close(fd);
  return linkage;
}

}  // namespace

bool UsesDilatedTime(const Image& image, const LaunchContext& context) {
  switch (image.manifest.time()) {
    case proto::ImageManifest::WALL:
      return false;
    case proto::ImageManifest::DILATED:
      return true;
    default:
      return context.realtime_factor != 0 && context.realtime_factor != 1.0;
  }
}

std::vector<std::string> SitlnetRuntimeFiles(const Image& image, const LaunchContext& context) {
  if (!UsesDilatedTime(image, context)) return {};
  return {kLibfaketime, kSocketTimeouts};
}

std::vector<std::string> PreloadLibraries(const Image& image, const LaunchContext& context) {
  std::vector<std::string> libraries = SitlnetRuntimeFiles(image, context);
  for (const auto& variable : image.manifest.env()) {
    if (variable.name() != "LD_PRELOAD") continue;
    const std::string value = ExpandPlaceholders(variable.value(), image, context);
    // ld.so(8): the list is separated by colons or spaces.
    for (size_t start = 0; start <= value.size();) {
      const size_t end = std::min(value.find_first_of(": ", start), value.size());
      if (end > start) libraries.push_back(value.substr(start, end - start));
      start = end + 1;
    }
  }
  return libraries;
}

std::vector<std::string> DilatedTimeEnvironment(const Image& image, const LaunchContext& context,
                                                const std::vector<std::string>& command) {
  if (!UsesDilatedTime(image, context)) return {};
  const std::string robot =
      "robot \"" + context.robot + "\": image \"" + image.manifest.name() + "\"";
  if (context.realtime_factor == 0) {
    throw Error(robot +
                " asks for time: DILATED, which needs realtime pacing (lockstep has no "
                "fixed realtime factor; " +
                image.manifest_path + ")");
  }
  if (access(kLibfaketime, R_OK) != 0) {
    throw Error(robot + " runs in dilated time, which needs libfaketime (" + kLibfaketime +
                ": apt-get install libfaketime; or time: WALL in " + image.manifest_path + ")");
  }
  if (access(kSocketTimeouts, R_OK) != 0) {
    throw Error(robot + " runs in dilated time, which needs " + kSocketTimeouts +
                " (built with sitlnet: cmake --build build)");
  }
  const std::string program = FindProgram(command.at(0));
  switch (LinkageOf(program)) {
    case Linkage::kStatic:
      throw Error(robot + ": " + program +
                  " is statically linked, so libfaketime cannot dilate its clock (time: WALL in " +
                  image.manifest_path + " to run it on the host's clock, or realtime_factor 1)");
    case Linkage::kGo:
      std::fprintf(stderr,
                   "%s: warning: %s: %s is a Go program, which reads its clock around "
                   "libc: its time is not dilated (docs/time.md)\n",
                   context.program.c_str(), robot.c_str(), program.c_str());
      break;
    default:
      break;
  }
  char factor[32];
  std::snprintf(factor, sizeof factor, "%.17g", context.realtime_factor);
  std::string preload = std::string(kLibfaketime) + ":" + kSocketTimeouts;
  for (const auto& variable : image.manifest.env()) {
    if (variable.name() == "LD_PRELOAD") preload += ":" + variable.value();
  }
  std::vector<std::string> env = {"LD_PRELOAD=" + preload,
                                  // The host's calendar time at start, then f times as fast.
                                  std::string("FAKETIME=+0 x") + factor,
                                  std::string("SITLNET_TIME_FACTOR=") + factor};
  // Children continue their parent's clock instead of restarting it (libfaketime keeps the
  // shared state in /dev/shm, which is the sandbox's own: nothing is left on the host).
  if (image.manifest.sandbox() == proto::ImageManifest::CONFINED) {
    env.push_back("FAKETIME_DONT_RESET=1");
  }
  return env;
}

}  // namespace sitlnet::images::internal
