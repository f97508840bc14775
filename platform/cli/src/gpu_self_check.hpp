#pragma once
// `vifusion run` until the synthetic benchmark lands: runs the preprocessing kernels and the
// normal-equation reduction on a built-in frame, checks them against the CPU references and
// prints what it measured.

#include <string>

namespace vifusion::cli {

struct SelfCheckOptions {
  std::string device;  ///< GPU name filter (empty: best device; VIFUSION_GPU_DEVICE also works)
  int width = 640;     ///< frame width [px], even
  int height = 480;    ///< frame height [px]
  int frames = 20;     ///< timed repetitions per step
};

/// Returns the process exit code: 0 when every check passed, 1 when a GPU result disagrees with
/// its CPU reference. Throws vifusion::Error on unusable devices or options.
int runGpuSelfCheck(const SelfCheckOptions& options);

}  // namespace vifusion::cli
