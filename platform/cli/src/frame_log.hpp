#pragma once
// frames.csv of `vifusion run`: one row per frame of what tracking saw and decided, so a run that
// drifts or loses frames can be read back frame by frame (which frames were lost, whether the view
// still landed on the map, where the time went). Columns, after a '#'-prefixed header:
//   t_ns                  the frame's camera time [ns]
//   tracking              0 tracked, 1 IMU-carried, 2 lost (slam/tracking_state.hpp)
//   lost                  1: tracking = 2: the pose is a guess and the frame was not fused
//   pose_sigma_m          IMU-carried and lost inertial frames: the pose's σ at the far end of the depth
//                         range, the quantity ImuCarryOptions bounds [m]; 0 otherwise
//   imu                   1: the estimator used this frame's IMU samples, 0: refused or rgbd mode
//   icp_inliers, icp_candidates, rgb_inliers   level-0 counts of the last iteration (FrameResult)
//   coverage              share of the frame's valid pixels the map's prediction at its pose covers (the
//                         fill-in fills the rest); −1: not fused
//   fill                  1: rgbd tracking used the previous frame's fill-in (slam/reference_fill.hpp): the
//                         map covered too little of the view, or the frame failed against the map alone
//   iterations            Gauss-Newton iterations over all levels
//   surfels               surfels in the map after the frame
//   active_surfels        of which in the active range the next frame's passes visit (map/map_buffers.hpp;
//                         all after a loop closure moved or reactivated surfels)
//   evicted               inactive surfels the map-full policy evicted in the frame
//   preprocess_ms, tracking_ms, mapping_ms      wall time of the stages [ms]
//   fusion_gpu_ms, maintenance_gpu_ms, prediction_gpu_ms, reference_gpu_ms   the map update's GPU stages
//                         (slam::MapStageTimes) [ms]; −1: not measured (no device timestamps, or not fused)
//   imu_chi2              the IMU term's χ² at the solution (inertial modes; 0 otherwise)
//   vision_chi2           how far the dense solution pulled the state from the IMU and the prior [χ²]
//   vision_rejected       1: the dense solution failed the estimator's gate on vision_chi2 (then lost = 1)
//   closure               the frame's loop-closure attempt (slam/loop_closure.hpp): 0 none, 1 accepted (the map
//                         was deformed and the trajectory with it), 2 refused, 3 agreed (the correction was
//                         within its noise and the layers within the depth noise: old surfaces reactivated,
//                         nothing moved)
//   closure_refusal       the refused attempt's failed test, slam::ClosureRefusal: 1 overlap, 2 diverged,
//                         3 residual, 4 unconstrained, 5 covariance, 6 correction, 7 solve, 8 consistency,
//                         9 ambiguous; 0 else
//   closure_error_mm      an attempt that reached the deformation: the mean constraint error after the solve [mm]
//   closure_inliers       the registration's ICP inliers between the active and inactive renderings (at level 0,
//                         or at the level where it found too little overlap)
//   closure_mean_chi2     the registration's mean χ² per inlier at its solution, the residual test's figure
//                         (RegistrationOptions::max_mean_chi2; 0 unless the registration got that far)
//   closure_sigma_mm, closure_sigma_deg   the registration's largest position and rotation σ (the covariance
//                         test's figures; 0 when it stopped for overlap)
//   closure_ms            wall time of the attempt [ms]
//   closure_correction_mm, closure_correction_deg, closure_chi2   the registration's correction (translation,
//                         rotation) and its χ² against the covariance (0 unless the registration got that far)
//   closure_free_directions  pose directions the registration left out as unconstrained by the surfaces in view
//                         (0–4, model_registration.hpp; 0 unless it got that far)
//   relocalised           1: lost to the recovery's guesses and tracked from a recognised place (relocaliser.hpp)
//   icp_energy            the ICP's mean normalised squared residual (slam/dense_tracker.hpp TrackingResult)
//   place_overlap, place_depth_agreeing, place_luma_ncc   a relocalised frame's agreement with its keyframe
//                         (loop/keyframe_agreement.hpp): overlapping blocks, those within the depth gate, luma NCC
//   map_search_hypotheses, map_search_verified, map_search_cost, map_search_inliers   a loaded map's camera that
//                         no keyframe placed, searched for in the whole map (slam::FrameResult's fields)
//   unreadable            1: the recorded frame could not be read and was skipped (report.json skipped_frames):
//                         t_ns is its listed time (−1 where the source lists none), tracking −1, and the other
//                         columns hold no measurement

#include <cstdio>
#include <filesystem>
#include <vector>

#include "vifusion/slam/slam.hpp"

namespace vifusion::cli {

/// Keeps the rows of a run in memory (reserved up front) and writes them at the end.
class FrameLog {
 public:
  explicit FrameLog(std::size_t frames) { rows_.reserve(frames); }

  void add(const slam::FrameResult& result);
  /// A recorded frame that could not be read, at its listed time (−1: unknown).
  void addUnreadable(std::int64_t t_ns);

  /// Writes frames.csv to `path` atomically (core/atomic_file.hpp); throws vifusion::Error naming
  /// the file when it cannot be written.
  void write(const std::filesystem::path& path) const;

 private:
  void print(std::FILE* file) const;
  struct Row {
    int64_t t_ns = 0;
    slam::TrackingState tracking = slam::TrackingState::kTracked;
    double pose_sigma_m = 0.0;
    bool imu = false;
    double icp_inliers = 0.0, icp_candidates = 0.0, rgb_inliers = 0.0;
    double coverage = 0.0;
    bool fill = false;
    int iterations = 0;
    uint32_t surfels = 0;
    uint32_t active_surfels = 0;
    uint32_t evicted = 0;
    double preprocess_ms = 0.0, tracking_ms = 0.0, mapping_ms = 0.0;
    slam::MapStageTimes map_stages;
    double imu_chi2 = 0.0;
    double vision_chi2 = 0.0;
    bool vision_rejected = false;
    int closure = 0;
    int closure_refusal = 0;
    double closure_error_mm = 0.0;
    double closure_inliers = 0.0;
    double closure_mean_chi2 = 0.0;
    double closure_sigma_mm = 0.0;
    double closure_sigma_deg = 0.0;
    double closure_ms = 0.0;
    double closure_correction_mm = 0.0;
    double closure_correction_deg = 0.0;
    double closure_chi2 = 0.0;
    int closure_free_directions = 0;
    bool relocalised = false;
    double icp_energy = 0.0;
    loop::KeyframeAgreement place_agreement;
    int map_search_hypotheses = 0;
    int map_search_verified = 0;
    double map_search_cost = 1.0;
    double map_search_inliers = 0.0;
    bool unreadable = false;
  };
  std::vector<Row> rows_;
};

}  // namespace vifusion::cli
