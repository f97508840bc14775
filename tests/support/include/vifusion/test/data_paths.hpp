#pragma once
#include <filesystem>

namespace vifusion::test {

/// The shared data folder: $VIFUSION_DATA_DIR when set, else ../shared/data beside the checkout.
std::filesystem::path dataDir();

}  // namespace vifusion::test
