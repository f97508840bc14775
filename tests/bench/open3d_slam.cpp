#include "open3d_slam.hpp"

#include <open3d/core/Device.h>
#include <open3d/core/Tensor.h>
#include <open3d/t/pipelines/odometry/RGBDOdometry.h>
#include <open3d/t/pipelines/slam/Frame.h>
#include <open3d/t/pipelines/slam/Model.h>
#include <open3d/utility/Logging.h>
#include <open3d/utility/Parallel.h>

#include <Eigen/Geometry>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <vector>

#include "timing.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/eval/metrics.hpp"

namespace vifusion::bench {
namespace {

namespace o3c = open3d::core;
namespace o3slam = open3d::t::pipelines::slam;
namespace o3odometry = open3d::t::pipelines::odometry;

// Open3D's defaults (examples/cpp/DenseSLAM.cpp and its reconstruction system's default config).
constexpr float kVoxelSizeM = 3.0f / 512.0f;   // ≈ 5.9 mm
constexpr int kBlockResolution = 16;           // voxels per block edge
constexpr int kBlockCount = 40000;             // the hash map's initial capacity [blocks]
constexpr float kDepthDiffM = 0.07f;           // odometry's outlier gate on the depth difference
constexpr float kTruncVoxelMultiplier = 8.0f;  // TSDF truncation = 8 voxels ≈ 4.7 cm
constexpr float kRaycastDepthMinM = 0.1f;      // where the raycast starts
constexpr double kMinFitness = 0.1;            // the example's acceptance: inlier share of the pixels …
constexpr double kMaxTranslationM = 0.15;      // … and the largest plausible motion per frame

SE3d se3FromTensor(const o3c::Tensor& T) {
  const o3c::Tensor cpu = T.To(o3c::Device("CPU:0"), o3c::Float64).Contiguous();
  const Eigen::Map<const Eigen::Matrix<double, 4, 4, Eigen::RowMajor>> m(cpu.GetDataPtr<double>());
  return SE3d(Eigen::Quaterniond(m.topLeftCorner<3, 3>()), m.topRightCorner<3, 1>());
}

/// Model::TrackFrameToModel(input, raycast, …, Method::PointToPlane) rebuilt from Open3D's public functions:
/// the body of its RGBDOdometryMultiScale + RGBDOdometryMultiScalePointToPlane (Open3D 0.16's
/// RGBDOdometry.cpp) step for step, except the 5×5 bilateral smoothing of the raycast depth before its
/// normals. Image::FilterBilateral on the CPU is IPP-ICV's, and Debian's libopen3d is built without IPP-ICV:
/// it throws "not implemented" on CPU:0, so Model::TrackFrameToModel cannot run there with any method
/// (Intensity and Hybrid need IPP's RGBToGray, FilterSobel and PyrDown as well). The raycast's normals come
/// from its unsmoothed vertex map: a TSDF raycast, already averaged over the fused frames.
o3odometry::OdometryResult trackFrameToModel(const o3slam::Frame& input, const o3slam::Frame& raycast,
                                             const PinholeCamera& camera, float depth_scale, float depth_max_m,
                                             const std::vector<o3odometry::OdometryConvergenceCriteria>& criteria,
                                             const o3odometry::OdometryLossParams& params) {
  using open3d::t::geometry::Image;
  const auto levels = static_cast<int>(criteria.size());
  std::vector<o3c::Tensor> source_vertex(criteria.size()), target_vertex(criteria.size()),
      target_normal(criteria.size()), intrinsics(criteria.size());
  // Metres, NaN outside (0, depth_max]; then the pyramid, finest level first, stored coarsest first.
  Image source = input.GetDataAsImage("depth").ClipTransform(depth_scale, 0.0f, depth_max_m, NAN);
  Image target = raycast.GetDataAsImage("depth").ClipTransform(depth_scale, 0.0f, depth_max_m, NAN);
  double scale = 1.0;  // Open3D halves fx, fy, cx and cy per level
  for (int i = 0; i < levels; ++i) {
    const auto slot = static_cast<std::size_t>(levels - 1 - i);
    intrinsics[slot] = o3c::Tensor::Init<double>(
        {{camera.fx * scale, 0.0, camera.cx * scale}, {0.0, camera.fy * scale, camera.cy * scale}, {0.0, 0.0, 1.0}});
    source_vertex[slot] = source.CreateVertexMap(intrinsics[slot], NAN).AsTensor();
    Image target_vertex_map = target.CreateVertexMap(intrinsics[slot], NAN);
    target_vertex[slot] = target_vertex_map.AsTensor();
    target_normal[slot] = target_vertex_map.CreateNormalMap(NAN).AsTensor();
    if (i + 1 < levels) {
      source = source.PyrDownDepth(params.depth_outlier_trunc_ * 2.0f, NAN);
      target = target.PyrDownDepth(params.depth_outlier_trunc_ * 2.0f, NAN);
      scale *= 0.5;
    }
  }
  // Open3D's Gauss-Newton loop and its stopping rule: relative changes of fitness and inlier RMSE both
  // below the criteria's (the first iteration never stops: its "previous" RMSE is 0).
  o3odometry::OdometryResult result(o3c::Tensor::Eye(4, o3c::Float64, o3c::Device("CPU:0")), 0.0, 1.0);
  for (std::size_t level = 0; level < criteria.size(); ++level) {
    for (int iteration = 0; iteration < criteria[level].max_iteration_; ++iteration) {
      const o3odometry::OdometryResult delta = o3odometry::ComputeOdometryResultPointToPlane(
          source_vertex[level], target_vertex[level], target_normal[level], intrinsics[level], result.transformation_,
          params.depth_outlier_trunc_, params.depth_huber_delta_);
      result.transformation_ = delta.transformation_.Matmul(result.transformation_);
      if (std::abs(result.fitness_ - delta.fitness_) / result.fitness_ < criteria[level].relative_fitness_ &&
          std::abs(result.inlier_rmse_ - delta.inlier_rmse_) / result.inlier_rmse_ < criteria[level].relative_rmse_) {
        break;
      }
      result.inlier_rmse_ = delta.inlier_rmse_;
      result.fitness_ = delta.fitness_;
    }
  }
  return result;
}

}  // namespace

Open3dRun runOpen3d(const Sequence& sequence, const preprocess::DepthToMetricParams& gate, const std::string& name) {
  // Open3D logs to stdout, which may carry the benchmark's JSON; errors only: 0.16.1's raycast warns on every
  // call that its range map needed one more fragment than it allocated (and reallocates).
  open3d::utility::Logger::GetInstance().SetPrintFunction(
      [](const std::string& message) { std::fprintf(stderr, "open3d: %s\n", message.c_str()); });
  open3d::utility::SetVerbosityLevel(open3d::utility::VerbosityLevel::Error);
  const o3c::Device device("CPU:0");
  const PinholeCamera& camera = sequence.calibration.camera;
  const o3c::Tensor intrinsics =
      o3c::Tensor::Init<double>({{camera.fx, 0.0, camera.cx}, {0.0, camera.fy, camera.cy}, {0.0, 0.0, 1.0}});
  const RgbdFrame& first = sequence.frames[0];
  const int width = first.depth.width();
  const int height = first.depth.height();
  const auto depth_scale = static_cast<float>(1.0 / first.depth_scale_m);  // raw units per metre
  const float depth_max_m = gate.max_depth_m;

  // Every frame as tensors before timing: raw uint16 depth and 8-bit RGB, each copied once.
  std::vector<o3c::Tensor> depth, colour;
  for (const RgbdFrame& frame : sequence.frames) {
    if (frame.depth_scale_m != first.depth_scale_m)
      throw Error("runOpen3d: the depth scale changes within the sequence");
    depth.emplace_back(frame.depth.data(), o3c::SizeVector{height, width, 1}, o3c::UInt16, device);
    colour.emplace_back(reinterpret_cast<const std::uint8_t*>(frame.rgb.data()), o3c::SizeVector{height, width, 3},
                        o3c::UInt8, device);
  }

  // Odometry's iterations per pyramid level, coarsest first (TrackFrameToModel's default).
  const std::vector<o3odometry::OdometryConvergenceCriteria> criteria = {6, 3, 1};
  const o3odometry::OdometryLossParams loss(kDepthDiffM);  // Huber deltas at Open3D's defaults
  Open3dRun run;
  run.threads = open3d::utility::EstimateMaxThreads();
  o3c::Tensor T_frame_to_world = o3c::Tensor::Eye(4, o3c::Float64, o3c::Device("CPU:0"));
  o3slam::Model model(kVoxelSizeM, kBlockResolution, kBlockCount, T_frame_to_world, device);
  o3slam::Frame input(height, width, intrinsics, device);
  o3slam::Frame raycast(height, width, intrinsics, device);

  // Frame 0, untimed: integrated at the identity, which must stay W for the ATE to compare with the others'.
  input.SetData("depth", depth[0]);
  input.SetData("color", colour[0]);
  model.UpdateFramePose(0, T_frame_to_world);
  model.Integrate(input, depth_scale, depth_max_m, kTruncVoxelMultiplier);
  model.SynthesizeModelFrame(raycast, depth_scale, kRaycastDepthMinM, depth_max_m, kTruncVoxelMultiplier, false);
  if (!model.GetCurrentFramePose().AllClose(o3c::Tensor::Eye(4, o3c::Float64, o3c::Device("CPU:0")), 0.0, 0.0)) {
    throw Error("runOpen3d: frame 0's pose is not the identity");
  }
  std::vector<eval::StampedPose> trajectory = {{first.t_ns, SE3d()}};

  double total_ms = 0.0;
  for (std::size_t i = 1; i < sequence.frames.size(); ++i) {
    input.SetData("depth", depth[i]);
    input.SetData("color", colour[i]);
    const auto start = std::chrono::steady_clock::now();
    bool tracked = false;
    try {
      // The transformation maps the input frame into the raycast's (the previous pose): T_previous_current.
      const o3odometry::OdometryResult result =
          trackFrameToModel(input, raycast, camera, depth_scale, depth_max_m, criteria, loss);
      const o3c::Tensor t = result.transformation_.Slice(0, 0, 3).Slice(1, 3, 4);
      const double translation_m = std::sqrt((t * t).Sum({0, 1}).Item<double>());
      if (result.fitness_ >= kMinFitness && translation_m < kMaxTranslationM) {
        T_frame_to_world = T_frame_to_world.Matmul(result.transformation_);
        tracked = true;
      } else {
        std::fprintf(stderr, "bench_rgbd_slam: Open3D's tracking rejected at frame %zu: fitness %.3f, %.3f m\n", i,
                     result.fitness_, translation_m);
      }
    } catch (const std::exception& e) {
      std::fprintf(stderr, "bench_rgbd_slam: Open3D's tracking threw at frame %zu: %s\n", i, e.what());
    }
    model.UpdateFramePose(static_cast<int>(i), T_frame_to_world);
    if (tracked) model.Integrate(input, depth_scale, depth_max_m, kTruncVoxelMultiplier);
    model.SynthesizeModelFrame(raycast, depth_scale, kRaycastDepthMinM, depth_max_m, kTruncVoxelMultiplier, false);
    total_ms += msSince(start);
    if (!tracked) ++run.failed_frames;
    trajectory.push_back({sequence.frames[i].t_ns, se3FromTensor(T_frame_to_world)});
  }
  run.ms_per_frame = total_ms / static_cast<double>(sequence.frames.size() - 1);
  run.ate_m = eval::ate(sequence.ground_truth, trajectory).rmse_m;
  writeTrajectory(name, trajectory);
  return run;
}

}  // namespace vifusion::bench
