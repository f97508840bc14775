#pragma once
// Open3D's tensor dense SLAM (open3d::t::pipelines::slam::Model: a TSDF voxel-block grid, frame-to-model
// point-to-plane odometry against its raycast) on the benchmark's frames: bench_rgbd_slam's second peer
// (speed and ATE), a dense frame-to-model system like ours where OpenCV's odometry is frame to frame.

#include <limits>
#include <string>

#include "bench_sequence.hpp"
#include "vifusion/preprocess/kernel_params.hpp"

namespace vifusion::bench {

struct Open3dRun {
  double ms_per_frame = 0.0;  ///< mean wall time of track + integrate + raycast over frames 1 … n−1
  double ate_m = std::numeric_limits<double>::quiet_NaN();
  int failed_frames = 0;  ///< tracking threw or was rejected: the pose is carried over, the frame not fused
  int threads = 0;        ///< OpenMP threads of Open3D's CPU kernels (utility::EstimateMaxThreads())
};

/// The loop of Open3D's own dense SLAM example (examples/cpp/DenseSLAM.cpp), on core::Device("CPU:0"):
/// frame 0 is integrated at the identity and raycast; every later frame is tracked against the previous
/// raycast, its pose updated, integrated (when tracked) and raycast for the next one, with Model's
/// Integrate and SynthesizeModelFrame. Tracking is Model::TrackFrameToModel's point-to-plane odometry
/// rebuilt from Open3D's public functions (ClipTransform, CreateVertexMap, CreateNormalMap, PyrDownDepth,
/// ComputeOdometryResultPointToPlane, its iteration and stopping rule), without the bilateral smoothing of
/// the raycast depth: Debian's Open3D 0.16.1 has no CPU FilterBilateral (IPP-ICV's), so TrackFrameToModel
/// itself throws on CPU:0 with every method (open3d_slam.cpp).
///
/// Whose values:
///   - ours: the intrinsics (calibration.yaml), depth_max = gate.max_depth_m (4.0 m; Open3D's default is 3.0 m)
///     for tracking, integration and raycasting, and depth_scale = 1 / frame.depth_scale_m (raw units per metre).
///   - Open3D's defaults (its example and its reconstruction system's config): voxel size 3/512 m, block
///     resolution 16, block count 40000, depth_diff 0.07 m, truncation 8 voxels, raycast from 0.1 m without
///     colour, point-to-plane odometry with criteria {6, 3, 1} iterations (coarsest level first) and
///     relative rmse / fitness 1e-6, Huber delta 0.05 m, and its example's acceptance test: a frame whose
///     tracking has fitness < 0.1 or moves ≥ 0.15 m is a failure (pose carried over, not integrated); an
///     exception is one too. Our depth gate's minimum (0.3 m) does not apply: Open3D has none in tracking
///     or integration.
/// Depth goes in as uint16 raw units, colour as 8-bit RGB (what Open3D's image reader gives its pipeline),
/// both wrapped as tensors before timing. Only the per-frame calls are timed (track + integrate + raycast);
/// a SLAM model has no untimed warm-up that leaves it unchanged, so frame 0 (first integration and raycast,
/// OpenMP's thread start) is the untimed one, as for our pipeline. Open3D's T_frame_to_world is our T_W_C;
/// frame 0's is checked to be the identity. Open3D's log goes to stderr (stdout may carry the JSON).
/// With --trajectory_dir the estimate is written as <name>.txt.
Open3dRun runOpen3d(const Sequence& sequence, const preprocess::DepthToMetricParams& gate, const std::string& name);

}  // namespace vifusion::bench
