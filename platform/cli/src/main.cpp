// vifusion: command-line front end. Subcommands grow with the issues; every one prints its
// options with defaults under --help and exits non-zero with a message on bad input.

#include <CLI/CLI.hpp>
#include <cstdio>

#include "gpu_self_check.hpp"
#include "vifusion/core/error.hpp"

int main(int argc, char** argv) {
  CLI::App app{"vifusion: dense RGB-D-inertial SLAM on Vulkan compute"};
  app.require_subcommand(1);

  vifusion::cli::SelfCheckOptions self_check;
  CLI::App* run = app.add_subcommand(
      "run", "Run the main job. Until the synthetic benchmark sequence lands this is the GPU self-check: "
             "preprocessing kernels and reduction on a built-in frame, checked against the CPU references");
  run->add_option("--device", self_check.device, "GPU name filter (default: best device; env VIFUSION_GPU_DEVICE)");
  run->add_option("--width", self_check.width, "Frame width [px], even")->capture_default_str()->check(CLI::Range(16, 4096));
  run->add_option("--height", self_check.height, "Frame height [px]")->capture_default_str()->check(CLI::Range(16, 4096));
  run->add_option("--frames", self_check.frames, "Timed repetitions per step")->capture_default_str()->check(CLI::Range(1, 100000));

  CLI11_PARSE(app, argc, argv);
  try {
    if (run->parsed()) return vifusion::cli::runGpuSelfCheck(self_check);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "vifusion: %s\n", error.what());
    return 2;
  }
  return 0;
}
