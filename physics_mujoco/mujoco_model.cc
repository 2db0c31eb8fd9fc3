#include "physics_mujoco/mujoco_model.h"

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "common/common.h"

namespace sitlnet::physics {
namespace {

std::atomic<long> g_warnings{0};

void OnMujocoError(const char* message) {
  std::fprintf(stderr, "sitlnet physics: MuJoCo error: %s\n", message);
  std::abort();
}

void OnMujocoWarning(const char* message) {
  // Print the first few only: a warning in the step loop would flood the log.
  if (g_warnings.fetch_add(1) < 20) {
    std::fprintf(stderr, "sitlnet physics: MuJoCo warning: %s\n", message);
  }
}

}  // namespace

void InstallMujocoHandlers() {
  static std::once_flag once;
  std::call_once(once, [] {
    mju_user_error = OnMujocoError;
    mju_user_warning = OnMujocoWarning;
  });
}

long MujocoWarningCount() { return g_warnings.load(); }

ModelPtr LoadModelFromXml(std::string_view xml, const std::string& what) {
  InstallMujocoHandlers();
  static constexpr char kFileName[] = "sitlnet_world.xml";
  // mjVFS holds 2000 file names of 1000 bytes: on the heap, never the stack.
  auto vfs = std::make_unique<mjVFS>();
  mj_defaultVFS(vfs.get());
  if (mj_makeEmptyFileVFS(vfs.get(), kFileName, static_cast<int>(xml.size())) != 0) {
    throw Error(what + ": cannot create MuJoCo VFS file");
  }
  const int index = mj_findFileVFS(vfs.get(), kFileName);
  SITLNET_DEMAND(index >= 0);
  std::memcpy(vfs->filedata[index], xml.data(), xml.size());
  char error[1000] = "";
  mjModel* model = mj_loadXML(kFileName, vfs.get(), error, sizeof error);
  // mj_deleteVFS frees every file; mj_deleteFileVFS has been seen to loop.
  mj_deleteVFS(vfs.get());
  if (model == nullptr) throw Error(what + ": MuJoCo rejected the model: " + error);
  return ModelPtr(model);
}

}  // namespace sitlnet::physics
