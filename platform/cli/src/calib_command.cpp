#include "calib_command.hpp"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>

#include "vifusion/calib/frame_signals.hpp"
#include "vifusion/calib/noise_estimator.hpp"
#include "vifusion/calib/pair_residuals.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/kalibr.hpp"

namespace vifusion::cli {
namespace {

/// A ground-truth pose counts as the frame's when their stamps differ by at most this [ns]: a sixth of a
/// 30 Hz frame interval, far below the interval, above any reader's stamp rounding.
constexpr std::int64_t kMaxPoseOffset_ns = 5'000'000;

std::optional<SE3d> poseAt(std::span<const datasets::StampedPose> poses, std::int64_t t_ns) {
  const auto after = std::lower_bound(poses.begin(), poses.end(), t_ns,
                                      [](const datasets::StampedPose& pose, std::int64_t t) { return pose.t_ns < t; });
  std::optional<SE3d> best;
  std::int64_t best_offset = kMaxPoseOffset_ns + 1;
  for (auto it = after == poses.begin() ? after : after - 1; it != poses.end() && it <= after; ++it) {
    const std::int64_t offset = std::abs(it->t_ns - t_ns);
    if (offset < best_offset) {
      best_offset = offset;
      best = it->T_world_body;
    }
  }
  return best;
}

}  // namespace

int runCalibNoise(const CalibNoiseOptions& options) {
  if (options.frame_step < 1) throw Error("calib noise: --frame-step must be ≥ 1");
  if (options.max_pairs < 1) throw Error("calib noise: --max-pairs must be ≥ 1");
  if (options.focal_baseline_px_m < 0.0) throw Error("calib noise: --focal-baseline must be > 0 px·m");
  const std::unique_ptr<datasets::DatasetReader> reader = datasets::openDataset(options.source);
  RigCalibration calibration = reader->calibration();
  const std::span<const datasets::StampedPose> poses = reader->groundTruth();
  if (poses.empty()) throw Error("calib noise: " + options.source + " has no ground-truth poses");
  double focal_baseline_px_m = options.focal_baseline_px_m;
  if (focal_baseline_px_m == 0.0) {
    if (!calibration.noise) {
      throw Error("calib noise: give --focal-baseline (the sensor's f·b [px·m]); " + options.source +
                  "'s calibration has no depth_noise");
    }
    focal_baseline_px_m = calibration.noise->depth.focal_baseline_px_m;
  }

  // Pairs (i, i + step) with i every `stride` frames, so that the pairs span the whole sequence.
  const int frames = static_cast<int>(reader->frameCount());
  const int stride = std::max(options.frame_step, (frames + options.max_pairs - 1) / options.max_pairs);
  calib::NoiseEstimator estimator(focal_baseline_px_m);
  const calib::DepthWindow window;
  const calib::PairResidualOptions residual_options;
  calib::FrameSignals anchor, current;
  std::optional<SE3d> T_W_anchor;
  int anchor_index = -1;
  calib::PairResidualImages residuals;
  RgbdFrame frame;
  for (int index = 0; reader->nextFrame(frame); ++index) {
    const bool is_anchor = index % stride == 0;
    const bool closes_pair = anchor_index >= 0 && index == anchor_index + options.frame_step;
    if (!is_anchor && !closes_pair) continue;
    const std::optional<SE3d> T_W_C = poseAt(poses, frame.t_ns);
    if (closes_pair && T_W_anchor && T_W_C) {
      current.assign(frame, calibration, window);
      calib::computePairResiduals(calibration.camera, anchor.inverse_depth_per_m.view(), anchor.grey.view(),
                                  current.inverse_depth_per_m.view(), current.grey.view(),
                                  T_W_C->inverse() * *T_W_anchor, residual_options, residuals);
      estimator.addPair(residuals);
      anchor_index = -1;
    }
    if (is_anchor && static_cast<int>(index / stride) < options.max_pairs) {
      anchor.assign(frame, calibration, window);
      T_W_anchor = T_W_C;
      anchor_index = index;
    }
  }

  const calib::NoiseEstimate estimate = estimator.estimate();
  const CameraNoiseModel& model = estimate.model;
  nlohmann::json bins = nlohmann::json::array();
  for (const calib::DepthBinNoise& bin : estimate.depth_bins) {
    bins.push_back({{"z_m", bin.z_m},
                    {"samples", bin.samples},
                    {"inverse_depth_sigma_per_m", bin.inverse_depth_sigma_per_m},
                    {"fitted_sigma_per_m", bin.fitted_sigma_per_m},
                    {"depth_sigma_m", bin.inverse_depth_sigma_per_m * bin.z_m * bin.z_m}});
  }
  const double bias_per_m = calibration.inverse_depth_bias_per_m + estimate.remaining_inverse_depth_bias_per_m;
  const nlohmann::json report = {
      {"source", reader->describe()},
      {"pairs", estimate.pairs},
      {"frame_step", options.frame_step},
      {"depth",
       {{"disparity_sigma_px", model.depth.disparity_sigma_px},
        {"focal_baseline_px_m", model.depth.focal_baseline_px_m},
        {"inverse_depth_sigma_per_m", model.depth.inverseDepthSigma()},
        {"quantisation_m", model.depth.quantisation_m},
        {"lateral_sigma_px", model.depth.lateral_sigma_px},
        {"correlation_px", model.depth.correlation_px},
        {"pixels_per_sample", model.depth.pixels_per_sample},
        {"samples", estimate.depth_samples},
        {"inverse_depth_bias_per_m", bias_per_m},
        {"inverse_depth_bias_sigma_per_m", estimate.remaining_inverse_depth_bias_sigma_per_m},
        {"calibration_inverse_depth_bias_per_m", calibration.inverse_depth_bias_per_m},
        {"bins", bins}}},
      {"intensity",
       {{"sigma", model.intensity.sigma},
        {"lateral_sigma_px", model.intensity.lateral_sigma_px},
        {"correlation_px", model.intensity.correlation_px},
        {"pixels_per_sample", model.intensity.pixels_per_sample},
        {"samples", estimate.intensity_samples}}}};
  std::printf("%s\n", report.dump().c_str());
  if (!options.out.empty()) {
    calibration.noise = model;
    calibration.noise->depth.inverse_depth_bias_sigma_per_m = estimate.remaining_inverse_depth_bias_sigma_per_m;
    calibration.inverse_depth_bias_per_m = bias_per_m;
    datasets::writeCalibrationYaml(options.out, calibration);
  }
  return 0;
}

}  // namespace vifusion::cli
