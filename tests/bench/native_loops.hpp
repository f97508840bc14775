#pragma once
// "Native" C++ loops doing the same work as the heaviest GPU kernels, for bench_rgbd_slam's ratio
// of each kernel to a plain CPU loop (issue 4: every kernel within 2.5× of such a loop). Plain -O3
// loops over the same buffers (read back from the GPU), with the project's compile flags: no
// intrinsics, no hand vectorisation, float arithmetic as the shaders, sums in double. They are
// timing baselines, not references: the CPU references in pipeline/*/src stay the correctness
// oracles (they follow the shaders operation for operation; these only have to do the same work).
//
// Each loop takes a pixel range, so the same code runs on one thread or split over two.

#include <array>
#include <cstdint>
#include <span>

#include "vifusion/preprocess/pixel_types.hpp"
#include "vifusion/tracking/icp_params.hpp"
#include "vifusion/tracking/photometric_params.hpp"

namespace vifusion::bench {

/// The 30 normal-equation sums (layout of shaders/include/reduce/normal_equations.glsl).
using NativeSums = std::array<double, 30>;

/// icp_reduce.comp's work over level pixels [begin, end): association by projection, gates, Huber
/// weight, J = [n, q × n], accumulated into `sums`.
void icpNative(const preprocess::VertexPixel* current_vertices, const preprocess::NormalPixel* current_normals,
               const preprocess::VertexPixel* model_vertices, const preprocess::NormalPixel* model_normals,
               const tracking::IcpParams& params, int begin, int end, NativeSums& sums);

/// photometric_reduce.comp's work over pixels [begin, end): projection, occlusion gate, bilinear
/// intensity and gradient, support gate (no hole of the prediction under the sample), J = [g, q × g],
/// Huber weight on σ² = σ_I² + σ_px²‖∇I‖².
void photometricNative(const preprocess::VertexPixel* current_vertices, const float* current_intensity,
                       const float* reference_intensity, const preprocess::GradientPixel* reference_gradients,
                       const preprocess::VertexPixel* reference_vertices, const tracking::PhotometricParams& params,
                       int begin, int end, NativeSums& sums);

/// Runs `loop(begin, end, sums)` over [0, count) on `threads` threads (1 or 2; the calling thread
/// takes the first part) and returns the sums added together.
template <typename Loop>
NativeSums runSplit(int count, int threads, Loop&& loop);

}  // namespace vifusion::bench

#include <thread>

namespace vifusion::bench {

template <typename Loop>
NativeSums runSplit(int count, int threads, Loop&& loop) {
  NativeSums first{}, second{};
  if (threads <= 1) {
    loop(0, count, first);
    return first;
  }
  const int half = count / 2;
  std::thread helper([&] { loop(half, count, second); });
  loop(0, half, first);
  helper.join();
  for (std::size_t k = 0; k < first.size(); ++k) first[k] += second[k];
  return first;
}

}  // namespace vifusion::bench
