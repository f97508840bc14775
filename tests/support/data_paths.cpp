#include "vifusion/test/data_paths.hpp"

#include <cstdlib>

namespace vifusion::test {

std::filesystem::path dataDir() {
  if (const char* env = std::getenv("VIFUSION_DATA_DIR"); env != nullptr && env[0] != '\0') {
    return env;
  }
  return VIFUSION_DEFAULT_DATA_DIR;
}

}  // namespace vifusion::test
