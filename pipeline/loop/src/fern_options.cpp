#include "vifusion/loop/fern_options.hpp"

#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {
namespace {

void require(bool ok, double value, const char* name, const char* condition) {
  if (!ok || !std::isfinite(value)) {
    throw Error(std::string("fern option '") + name + "' = " + std::to_string(value) + " must be finite and " +
                condition);
  }
}

}  // namespace

void FernOptions::validate() const {
  require(num_ferns >= 1 && num_ferns <= 65535, num_ferns, "num_ferns", "in [1, 65535]");
  require(downsample_factor >= 1 && downsample_factor <= 64, downsample_factor, "downsample_factor", "in [1, 64]");
  require(min_depth_m > 0.0f, min_depth_m, "min_depth_m", "> 0");
  require(max_depth_m > min_depth_m, max_depth_m, "max_depth_m", "> min_depth_m");
  require(keyframe_threshold >= 0.0 && keyframe_threshold < 1.0, keyframe_threshold, "keyframe_threshold", "in [0, 1)");
  require(min_valid_fraction > 0.0 && min_valid_fraction <= 1.0, min_valid_fraction, "min_valid_fraction", "in (0, 1]");
  require(capacity >= 1 && capacity <= 1'000'000, capacity, "capacity", "in [1, 1000000]");
}

}  // namespace vifusion::loop
