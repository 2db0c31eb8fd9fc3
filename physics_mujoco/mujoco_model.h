// MuJoCo plumbing: error handlers, loading MJCF text through a VFS, RAII owners.
#ifndef SITLNET_PHYSICS_MUJOCO_MUJOCO_MODEL_H_
#define SITLNET_PHYSICS_MUJOCO_MUJOCO_MODEL_H_

#include <mujoco/mujoco.h>

#include <memory>
#include <string>
#include <string_view>

namespace sitlnet::physics {

struct ModelDeleter {
  void operator()(mjModel* model) const { mj_deleteModel(model); }
};
struct DataDeleter {
  void operator()(mjData* data) const { mj_deleteData(data); }
};
using ModelPtr = std::unique_ptr<mjModel, ModelDeleter>;
using DataPtr = std::unique_ptr<mjData, DataDeleter>;

// Installs sitlnet's mju_user_error (prints and aborts: MuJoCo cannot continue after an
// error, and the default handler waits for Enter) and mju_user_warning (prints, counts).
// Idempotent, thread-safe.
void InstallMujocoHandlers();

// Number of MuJoCo warnings reported through mju_user_warning since start.
long MujocoWarningCount();

// Compiles MJCF text. MuJoCo 2.2.2 has no load-from-string API: the text goes into a
// heap-allocated mjVFS (about 2 MB) freed with mj_deleteVFS. Throws Error naming
// `what` and MuJoCo's message when the model does not compile.
ModelPtr LoadModelFromXml(std::string_view xml, const std::string& what);

}  // namespace sitlnet::physics

#endif  // SITLNET_PHYSICS_MUJOCO_MUJOCO_MODEL_H_
