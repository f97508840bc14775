#include "vifusion/core/version.hpp"

// VIFUSION_VERSION is defined for this file alone (pipeline/core/CMakeLists.txt), so a new version
// recompiles one file.
namespace vifusion {

const char* versionString() { return VIFUSION_VERSION; }

}  // namespace vifusion
