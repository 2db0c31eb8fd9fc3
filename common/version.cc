// sitlnet's version, baked in when cmake configured the build (CMakeLists.txt sets
// SITLNET_GIT_COMMIT on this file alone, so a new commit recompiles only it).
#include "common/common.h"

#ifndef SITLNET_GIT_COMMIT
#define SITLNET_GIT_COMMIT "unknown"
#endif

namespace sitlnet {

std::string_view SitlnetVersion() { return SITLNET_GIT_COMMIT; }

}  // namespace sitlnet
