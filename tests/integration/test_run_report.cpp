// Checks the report.json (and frames.csv, trajectory.txt) files that `vifusion run` wrote for 2 s of the noisy
// synthetic living room (all three modes), the 50 real 7-Scenes frames, the wall-and-ceiling stretch of
// living_room_1 and the revisit walk with and without a covered camera (ctest fixtures integration.run_*).

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "vifusion/slam/dense_tracker.hpp"
#include "vifusion/slam/loop_closure.hpp"
#include "vifusion/slam/model_registration.hpp"

namespace vifusion {
namespace {

nlohmann::json report(const std::string& run_dir = VIFUSION_RUN_DIR, const std::string& name = "report.json") {
  std::ifstream file(run_dir + "/" + name);
  EXPECT_TRUE(file.good()) << "no " << name << " in " << run_dir;
  return nlohmann::json::parse(file);
}

/// frames.csv of a run: the header's column names and the rows as numbers.
struct FrameTable {
  std::vector<std::string> columns;
  std::vector<std::vector<double>> rows;
  double at(std::size_t row, const std::string& column) const {
    for (std::size_t c = 0; c < columns.size(); ++c) {
      if (columns[c] == column) return rows.at(row).at(c);
    }
    ADD_FAILURE() << "frames.csv has no column " << column;
    return 0.0;
  }
};

FrameTable frameTable(const std::string& run_dir) {
  std::ifstream file(run_dir + "/frames.csv");
  EXPECT_TRUE(file.good()) << "no frames.csv in " << run_dir;
  FrameTable table;
  std::string line, cell;
  std::getline(file, line);
  EXPECT_EQ(line.rfind('#', 0), 0u) << "the header starts with '#'";
  std::istringstream header(line.substr(1));
  while (std::getline(header, cell, ',')) table.columns.push_back(cell);
  while (std::getline(file, line)) {
    std::istringstream fields(line);
    std::vector<double>& row = table.rows.emplace_back();
    while (std::getline(fields, cell, ',')) row.push_back(std::stod(cell));
    EXPECT_EQ(row.size(), table.columns.size()) << line;
  }
  return table;
}

/// frames.csv agrees with report.json: one row per frame, stamps increasing, the frames and longest run
/// of each tracking state and the final surfel count the report gives, `imu_used` on every frame in the
/// inertial modes, and (in a `consistent` run) no dense solution refused by the estimator's gate.
void expectFramesCsvMatchesTheReport(const std::string& run_dir, bool inertial, bool consistent = true) {
  const nlohmann::json r = report(run_dir);
  const FrameTable table = frameTable(run_dir);
  ASSERT_EQ(static_cast<int>(table.rows.size()), r.at("frames").get<int>());
  double lost = 0.0, imu = 0.0, evicted = 0.0, rejected = 0.0, accepted = 0.0, refused = 0.0, agreed = 0.0;
  double state_frames[3] = {}, longest_run[3] = {}, run = 0.0;
  for (std::size_t i = 0; i < table.rows.size(); ++i) {
    const double state = table.at(i, "tracking");
    ASSERT_TRUE(state == 0.0 || state == 1.0 || state == 2.0) << "row " << i;
    const auto s = static_cast<std::size_t>(state);
    state_frames[s] += 1.0;
    run = i > 0 && table.at(i - 1, "tracking") == state ? run + 1.0 : 1.0;
    longest_run[s] = std::max(longest_run[s], run);
    EXPECT_EQ(table.at(i, "lost"), state == 2.0 ? 1.0 : 0.0) << "row " << i;
    if (!inertial) {
      EXPECT_NE(state, 1.0) << "only the inertial modes have an IMU to carry the pose, row " << i;
    }
    lost += table.at(i, "lost");
    rejected += table.at(i, "vision_rejected");
    EXPECT_TRUE(table.at(i, "vision_rejected") == 0.0 || state != 0.0) << "a refused frame is not tracked, row " << i;
    imu += table.at(i, "imu");
    // 0 none, 1 accepted, 2 refused, 3 agreed (frame_log.hpp)
    const double closure = table.at(i, "closure");
    ASSERT_TRUE(closure == 0.0 || closure == 1.0 || closure == 2.0 || closure == 3.0) << "row " << i;
    accepted += closure == 1.0 ? 1.0 : 0.0;
    refused += closure == 2.0 ? 1.0 : 0.0;
    agreed += closure == 3.0 ? 1.0 : 0.0;
    EXPECT_EQ(closure == 2.0, table.at(i, "closure_refusal") != 0.0) << "a refusal names its test, row " << i;
    // The residual test's figure (slam/model_registration.hpp): an accepted or agreed registration passed it, one
    // refused for the residual failed it.
    const double mean_chi2 = table.at(i, "closure_mean_chi2");
    const double max_mean_chi2 = slam::RegistrationOptions{}.max_mean_chi2;
    if (closure == 1.0 || closure == 3.0) {
      EXPECT_GT(mean_chi2, 0.0) << "row " << i;
      EXPECT_LE(mean_chi2, max_mean_chi2) << "row " << i;
    }
    if (table.at(i, "closure_refusal") == static_cast<double>(slam::ClosureRefusal::kResidual)) {
      EXPECT_GT(mean_chi2, max_mean_chi2) << "row " << i;
    }
    evicted += table.at(i, "evicted");
    EXPECT_LE(table.at(i, "active_surfels"), table.at(i, "surfels")) << "row " << i;
    // The map update's GPU stages: lavapipe has timestamps; a fused frame times all four, a lost one the last two.
    const bool fused = state != 2.0;
    for (const char* stage : {"fusion_gpu_ms", "maintenance_gpu_ms", "prediction_gpu_ms", "reference_gpu_ms"}) {
      const bool measured =
          fused || std::string(stage) == "prediction_gpu_ms" || std::string(stage) == "reference_gpu_ms";
      if (measured) {
        EXPECT_GE(table.at(i, stage), 0.0) << stage << ", row " << i;
      } else {
        EXPECT_EQ(table.at(i, stage), -1.0) << stage << ", row " << i;
      }
    }
    if (i == 0) continue;  // the first frame starts the map: nothing to track against
    EXPECT_GT(table.at(i, "t_ns"), table.at(i - 1, "t_ns")) << "row " << i;
    if (state == 0.0) {
      // The health test (DenseTracker::healthy). In rgbd mode, where no stable surfel is in view yet, there
      // may be no ICP candidates and the photometric term on the reference's fill-in registers the frame
      // alone.
      EXPECT_GE(table.at(i, "icp_inliers"), 0.2 * table.at(i, "icp_candidates")) << "row " << i;
      EXPECT_GT(table.at(i, "icp_inliers") + table.at(i, "rgb_inliers"), 0.0) << "row " << i;
    }
  }
  EXPECT_EQ(lost, r.at("lost_frames").get<double>());
  const char* names[3] = {"tracked", "imu_carried", "lost"};
  for (std::size_t s = 0; s < 3; ++s) {
    EXPECT_EQ(state_frames[s], r.at("tracking_states").at(names[s]).at("frames").get<double>()) << names[s];
    EXPECT_EQ(longest_run[s], r.at("tracking_states").at(names[s]).at("longest_run").get<double>()) << names[s];
  }
  EXPECT_EQ(table.at(table.rows.size() - 1, "surfels"), r.at("surfels").get<double>());
  // The budget: stage means that add up, and the GPU stages ranked by their mean.
  const nlohmann::json& wall = r.at("ms_per_frame");
  EXPECT_NEAR(
      wall.at("total").get<double>(),
      wall.at("preprocess").get<double>() + wall.at("tracking").get<double>() + wall.at("mapping").get<double>(), 1e-9);
  EXPECT_LE(wall.at("closure").get<double>(), wall.at("mapping").get<double>());
  const nlohmann::json& gpu = r.at("gpu_ms_per_frame");
  ASSERT_EQ(gpu.at("ranking").size(), 4u);
  for (std::size_t k = 1; k < 4; ++k) {
    EXPECT_GE(gpu.at(gpu.at("ranking")[k - 1].get<std::string>()).get<double>(),
              gpu.at(gpu.at("ranking")[k].get<std::string>()).get<double>());
  }
  EXPECT_EQ(evicted, r.at("map_evicted_surfels").get<double>());
  const nlohmann::json& closures = r.at("closures");
  EXPECT_EQ(accepted, closures.at("accepted").get<double>());
  EXPECT_EQ(agreed, closures.at("agreed").get<double>());
  double refused_in_report = 0.0;
  for (const auto& [test, count] : closures.at("refused").items()) refused_in_report += count.get<double>();
  EXPECT_EQ(refused, refused_in_report);
  if (consistent) {
    EXPECT_EQ(rejected, 0.0) << "a consistent run: the estimator's gate refuses nothing";
  }
  // The estimator starts at the first frame with IMU samples before it; every later frame uses them.
  if (inertial) {
    EXPECT_GE(imu, static_cast<double>(table.rows.size() - 1));
  } else {
    EXPECT_EQ(imu, 0.0);
  }
}

TEST(RunReport, FramesCsvHoldsEveryFrameOfTheRun) {
  expectFramesCsvMatchesTheReport(VIFUSION_RUN_DIR, false);
  expectFramesCsvMatchesTheReport(VIFUSION_RGBDI_RUN_DIR, true);
}

TEST(RunReport, RgbdRunsTheSyntheticLivingRoomEndToEnd) {
  const nlohmann::json r = report();
  EXPECT_EQ(r.at("frames").get<int>(), 61);
  EXPECT_GT(r.at("arena_bytes").get<double>(), 0.0);
  // Frame-to-model tracking on noisy 320×240 frames (measured: 6.5 mm ATE, nothing lost over 2 s; 12.5 mm
  // before the depth's inverse-depth bias was removed). The bound leaves room for driver float rounding.
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.015);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  EXPECT_GT(r.at("surfels").get<double>(), 10000.0);
  EXPECT_GT(r.at("map_ply_surfels").get<double>(), 1000.0);
}

TEST(RunReport, RgbdTracksTheRealSevenScenesFrames) {
  const nlohmann::json r = report(VIFUSION_SEVEN_SCENES_RUN_DIR);
  EXPECT_EQ(r.at("frames").get<int>(), 50);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  // Measured 11.5 mm against the provided poses (frame-to-frame odometry gave 18.8 mm).
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.030);
}

TEST(RunReport, RgbdInertialTracksTheSyntheticLivingRoomAndItsStates) {
  const nlohmann::json r = report(VIFUSION_RGBDI_RUN_DIR);
  EXPECT_EQ(r.at("mode").get<std::string>(), "rgbdi");
  EXPECT_EQ(r.at("frames").get<int>(), 61);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  EXPECT_EQ(r.at("frames_with_imu_issues").get<int>(), 0);
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.020);
  // states.csv against the simulator's states. 2 s at 320×240 is too short for the acceptance's 5 s /
  // 15 s windows and its estimates have not converged (measured: velocity 6.2 cm/s RMS, gravity 0.76°,
  // b_g 7.7e-3 rad/s at the end, ATE 10.0 mm; the first 200 frames of living_room_1 at 640×480 give
  // 1.0 cm/s after 5 s, 0.35°, 7e-4 rad/s, 2.6 mm): the bounds catch a broken estimator, not accuracy.
  const nlohmann::json states = report(VIFUSION_RGBDI_RUN_DIR, "eval.json").at("states");
  EXPECT_EQ(states.at("samples").get<int>(), 61);
  EXPECT_LT(states.at("velocity_rms_mps").get<double>(), 0.15);
  EXPECT_LT(states.at("gravity_final_deg").get<double>(), 4.0);
  EXPECT_LT(states.at("gyro_bias_final_rad_s").get<double>(), 0.02);
}

TEST(RunReport, GyroModeTracksTheSyntheticLivingRoom) {
  const nlohmann::json r = report(VIFUSION_GYRO_RUN_DIR);
  EXPECT_EQ(r.at("mode").get<std::string>(), "gyro");
  EXPECT_EQ(r.at("frames").get<int>(), 61);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.015);  // measured 6.3 mm
  EXPECT_EQ(report(VIFUSION_GYRO_RUN_DIR, "eval.json").at("states").at("samples").get<int>(), 61);
}

// Issue 4: the wall-and-ceiling view of living_room_1 (integration.run_rgbd.living_room_1_wall_ceiling).
// The model then covers half of the view; the photometric term sampled the hole rims of the
// prediction as edges and the coarse ICP slid along the wall-ceiling edge, and the pose ran away
// (ATE 0.65 m, 0 lost). Measured after the fixes: 4.4 mm, 0 lost (seed 2: 4.3 mm); with the depth's
// inverse-depth bias removed 2.1 mm.
TEST(RunReport, RgbdHoldsTheWallAndCeilingViewOfLivingRoom1) {
  const nlohmann::json r = report(VIFUSION_WALL_CEILING_RUN_DIR);
  EXPECT_EQ(r.at("frames").get<int>(), 52);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.010);
}

// Issue 5: the first 13 s of white_wall at 320×240 (integration.run_*.white_wall). On the wall nothing
// photometric is left and the ICP leaves the in-plane motion free: the IMU dead-reckons it for 3.8 s
// (0.28 m of drift) and the dense terms must take the pose back when the room returns. Measured:
// RGB-D-inertial 39.5 mm, 0 lost (46.6 mm before the depth's inverse-depth bias was removed; 1016 mm,
// 58 lost before the estimator's gate and step check, the return diverged along the wall); RGB-D alone
// (the comparison runs without relocalisation) 2.28 m, 76 lost. The bound is the acceptance's, which is for
// the whole sequence at 640×480.
TEST(RunReport, RgbdInertialCrossesTheWhiteWall) {
  const nlohmann::json inertial = report(VIFUSION_WHITE_WALL_RGBDI_RUN_DIR);
  const nlohmann::json rgbd = report(VIFUSION_WHITE_WALL_RGBD_RUN_DIR);
  EXPECT_EQ(inertial.at("frames").get<int>(), 391);
  EXPECT_EQ(inertial.at("lost_frames").get<int>(), 0);
  EXPECT_LT(inertial.at("ate_rmse_m").get<double>(), 0.050);
  EXPECT_GT(rgbd.at("ate_rmse_m").get<double>(), 3.0 * inertial.at("ate_rmse_m").get<double>());
  // The return to the room closes loops (issue 16): none of them false against the ground truth.
  EXPECT_EQ(inertial.at("closures_against_ground_truth").at("false").get<int>(), 0);
  expectFramesCsvMatchesTheReport(VIFUSION_WHITE_WALL_RGBDI_RUN_DIR, true, false);
}

// Issue 15: the first 11 s of unmapped_turn at 320×240 in rgbdi (integration.run_rgbdi.unmapped_turn): a
// 180° turn in 1.4 s into the half of the room the map has not seen. The stable map lags such a turn by
// the ten observations a surfel needs; where the dense terms fail, the IMU carries the pose while the map
// grows at it, and the dense terms take over again. Measured: 5.7 mm, 0 lost, 18 frames IMU-carried in one
// run; before (234f8fd) 108 mm with 107 frames lost for good.
TEST(RunReport, RgbdInertialTurnsIntoTheUnmappedHalfOfTheRoom) {
  const nlohmann::json r = report(VIFUSION_UNMAPPED_TURN_RUN_DIR);
  EXPECT_EQ(r.at("frames").get<int>(), 331);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  EXPECT_LE(r.at("tracking_states").at("imu_carried").at("longest_run").get<int>(), 30);
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.010);
  expectFramesCsvMatchesTheReport(VIFUSION_UNMAPPED_TURN_RUN_DIR, true, false);
}

// Issue 16: sim:revisit at 160×120 in rgbd (integration.run_*.revisit): the walk comes back to its first view
// 23 s later after two half turns. Open loop it arrives with the drift of the way; local loop closure must
// register the active model against the inactive one there, deform the map and the trajectory, and cut the
// ATE by at least the factor (its acceptance asks ≤ 0.6× open loop at 640×480); tests/bench/README.md
// has the measured ratios.
TEST(RunReport, LoopClosureOnTheRevisitDeformsTheMapAndCutsTheAte) {
  constexpr double kMaxAteRatio = 0.6;
  const nlohmann::json closed = report(VIFUSION_REVISIT_CLOSED_RUN_DIR);
  const nlohmann::json open = report(VIFUSION_REVISIT_OPEN_RUN_DIR);
  EXPECT_EQ(closed.at("lost_frames").get<int>(), 0);
  EXPECT_EQ(open.at("lost_frames").get<int>(), 0);
  EXPECT_GE(closed.at("closures").at("accepted").get<int>(), 1);
  EXPECT_EQ(open.at("closures").at("accepted").get<int>(), 0);
  EXPECT_LE(closed.at("ate_rmse_m").get<double>(), kMaxAteRatio * open.at("ate_rmse_m").get<double>());
  // Stage timings: every attempt registered, every accepted closure solved and applied, every agreed one
  // applied (reactivation only).
  const nlohmann::json& closures = closed.at("closures");
  const nlohmann::json& stages = closures.at("stages_ms");
  int refused = 0;
  for (const auto& [test, count] : closures.at("refused").items()) refused += count.get<int>();
  const int accepted = closures.at("accepted").get<int>();
  EXPECT_GE(stages.at("registration").at("count").get<int>(), accepted + refused);
  EXPECT_GE(stages.at("deformation").at("count").get<int>(), accepted);
  EXPECT_EQ(stages.at("apply").at("count").get<int>(), accepted + closures.at("agreed").get<int>());
  for (const char* stage : {"registration", "deformation", "apply"}) {
    EXPECT_GT(stages.at(stage).at("mean").get<double>(), 0.0) << stage;
    EXPECT_LE(stages.at(stage).at("mean").get<double>(), stages.at(stage).at("max").get<double>()) << stage;
  }
  // Judged against the ground truth (platform/cli closure_judge.hpp): no accepted closure moved the pose away
  // from the truth beyond the registration's own 3σ.
  const nlohmann::json& judged = closed.at("closures_against_ground_truth");
  EXPECT_EQ(judged.at("judged").get<int>(), accepted);
  EXPECT_EQ(judged.at("false").get<int>(), 0)
      << "worst error increase " << judged.at("worst_error_increase_mm").get<double>() << " mm";
  expectFramesCsvMatchesTheReport(VIFUSION_REVISIT_CLOSED_RUN_DIR, false);
  expectFramesCsvMatchesTheReport(VIFUSION_REVISIT_OPEN_RUN_DIR, false);
}

/// A TUM pose file (timestamp tx ty tz qx qy qz qw; '#' comments) as T_world_camera per row.
std::vector<Eigen::Isometry3d> tumPoses(const std::string& path) {
  std::ifstream file(path);
  EXPECT_TRUE(file.good()) << "cannot read " << path;
  std::vector<Eigen::Isometry3d> poses;
  std::string line;
  while (std::getline(file, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    double t, x, y, z, qx, qy, qz, qw;
    fields >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
    EXPECT_FALSE(fields.fail()) << path << ": " << line;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = Eigen::Quaterniond(qw, qx, qy, qz).normalized().toRotationMatrix();
    T.translation() = Eigen::Vector3d(x, y, z);
    poses.push_back(T);
  }
  return poses;
}

/// RMS position error [m] of a run's trajectory over frames [first, last] against the dataset's ground truth,
/// both taken in the first camera's frame (the run's world): no alignment, so drift before `first` counts, as
/// it does for a robot.
double rmsPositionErrorM(const std::string& run_dir, const std::string& dataset_dir, std::size_t first,
                         std::size_t last) {
  const std::vector<Eigen::Isometry3d> estimate = tumPoses(run_dir + "/trajectory.txt");
  const std::vector<Eigen::Isometry3d> truth = tumPoses(dataset_dir + "/groundtruth.txt");
  EXPECT_GT(estimate.size(), last);
  EXPECT_GT(truth.size(), last);
  if (estimate.size() <= last || truth.size() <= last || truth.empty()) return INFINITY;
  const Eigen::Isometry3d T_C0_world = truth.front().inverse();
  double sum_m2 = 0.0;
  for (std::size_t k = first; k <= last; ++k) {
    sum_m2 += (estimate[k].translation() - (T_C0_world * truth[k]).translation()).squaredNorm();
  }
  return std::sqrt(sum_m2 / static_cast<double>(last - first + 1));
}

// Issue 16's relocalisation criterion, shortened: the revisit walk with the camera covered for 2 s (frames
// black, no depth: integration.run_rgbd.revisit_covered blanks them on replay) from 24 s, while the camera moves on
// along the views of the first pass. In rgbd the recovery's guesses (the last pose, the continued motion) are 2 s
// stale; the relocaliser must recognise the place among the first pass's keyframes and track from it within 1 s of the
// cover's end, and the trajectory after the gap must be within 1.5× of the uncovered run's over the same frames.
TEST(RunReport, ACoveredCameraRelocalisesOnTheMappedRevisit) {
  constexpr double kFrameRateHz = 30.0;
  constexpr double kMaxRelocalisationS = 1.0;
  constexpr double kMaxErrorRatio = 1.5;
  const nlohmann::json covered = report(VIFUSION_REVISIT_COVERED_RUN_DIR);
  const FrameTable table = frameTable(VIFUSION_REVISIT_COVERED_RUN_DIR);
  constexpr std::size_t cover_first = VIFUSION_REVISIT_COVER_FIRST;
  constexpr std::size_t cover_end = cover_first + VIFUSION_REVISIT_COVER_FRAMES;
  ASSERT_GT(table.rows.size(), cover_end + 30);
  std::size_t first_lost = 0;
  while (first_lost < table.rows.size() && table.at(first_lost, "lost") == 0.0) ++first_lost;
  EXPECT_GE(first_lost, cover_first) << "lost before the cover";
  EXPECT_LE(first_lost, cover_first) << "a covered frame cannot be tracked";
  std::size_t back = first_lost;
  while (back < table.rows.size() && table.at(back, "lost") == 1.0) ++back;
  ASSERT_LT(back, table.rows.size()) << "never tracked again after the cover";
  EXPECT_GE(back, cover_end) << "a covered frame cannot be tracked";
  EXPECT_LE(static_cast<double>(back) - static_cast<double>(cover_end), kMaxRelocalisationS * kFrameRateHz)
      << "first tracked frame after the cover: " << back;
  EXPECT_EQ(table.at(back, "relocalised"), 1.0) << "the 2 s old guesses must not be what tracks, row " << back;
  // The relocalised frame agrees with its keyframe image to image (the same place, seen again): most of its
  // overlapping blocks within the depth gate, its colour correlated (printed for tests/bench/README.md).
  const double overlap = table.at(back, "place_overlap"), agreeing = table.at(back, "place_depth_agreeing");
  std::printf("  relocalised frame: %.0f overlapping blocks, %.0f within the depth gate, luma NCC %.3f\n", overlap,
              agreeing, table.at(back, "place_luma_ncc"));
  EXPECT_GT(overlap, 0.0);
  EXPECT_LE(agreeing, overlap);
  for (std::size_t i = back; i < table.rows.size(); ++i) EXPECT_EQ(table.at(i, "lost"), 0.0) << "row " << i;
  EXPECT_GE(covered.at("relocalisation").at("relocalisations").get<int>(), 1);
  EXPECT_GT(covered.at("relocalisation").at("keyframes").get<int>(), 0);

  // The uncovered run stops at REVISIT_FRAMES; the covered one replays the whole sequence, a frame more.
  const auto uncovered_frames = report(VIFUSION_REVISIT_CLOSED_RUN_DIR).at("frames").get<std::size_t>();
  const std::size_t last = std::min(table.rows.size(), uncovered_frames) - 1;
  const double covered_m = rmsPositionErrorM(VIFUSION_REVISIT_COVERED_RUN_DIR, VIFUSION_REVISIT_DATASET, back, last);
  const double uncovered_m = rmsPositionErrorM(VIFUSION_REVISIT_CLOSED_RUN_DIR, VIFUSION_REVISIT_DATASET, back, last);
  EXPECT_LE(covered_m, kMaxErrorRatio * uncovered_m)
      << "after the gap: covered " << 1e3 * covered_m << " mm, uncovered " << 1e3 * uncovered_m << " mm";
  expectFramesCsvMatchesTheReport(VIFUSION_REVISIT_COVERED_RUN_DIR, false);
}

// Issue 15: the first 36 s of sim:long at 160×120 in rgbd, open loop (integration.run_rgbd.long). Where the camera
// faces a blank wall, neither the ICP (one plane) nor the photometric term (no texture) sees the motion along it, and
// the pose used to slide while every frame passed the tracking tests — to 5 m/s against 0.3 m/s true, then 579 frames
// lost in a row continuing that velocity. Slam now loses a frame that moved faster than the platform can
// (TrackerOptions::max_speed_mps) and drops the slide's velocity, and relocalisation takes over. Asserted: no tracked
// pose moved faster than that since the frame it was tracked from (the last tracked one; a relocalised frame starts
// afresh); the run stays within the room's size in ATE. How long it stays lost is printed, not asserted: whether the
// lag along the wall at the start ends in one lost frame or in 12 s turns on changes of the depth bias far below its
// σ (tests/bench/README.md, "Whether that run recovers is chance"), so a bound on it would test luck.
TEST(RunReport, RgbdLosesAPoseSlidingFasterThanThePlatformInsteadOfTrackingIt) {
  constexpr double kRoomSizeM = 2.0;  // ATE of a pose that slid out of the room
  const nlohmann::json r = report(VIFUSION_LONG_RGBD_RUN_DIR);
  const FrameTable table = frameTable(VIFUSION_LONG_RGBD_RUN_DIR);
  const std::vector<Eigen::Isometry3d> poses = tumPoses(std::string(VIFUSION_LONG_RGBD_RUN_DIR) + "/trajectory.txt");
  ASSERT_EQ(poses.size(), table.rows.size());
  const double max_speed_mps = slam::TrackerOptions{}.max_speed_mps;
  double fastest_mps = 0.0;
  std::size_t reference = 0;
  for (std::size_t i = 1; i < table.rows.size(); ++i) {
    if (table.at(i, "tracking") != 0.0) continue;
    if (table.at(i, "relocalised") == 0.0) {
      const double dt_s = (table.at(i, "t_ns") - table.at(reference, "t_ns")) * 1e-9;
      const double speed_mps = (poses[i].translation() - poses[reference].translation()).norm() / dt_s;
      fastest_mps = std::max(fastest_mps, speed_mps);
      EXPECT_LE(speed_mps, max_speed_mps * (1.0 + 1e-6)) << "row " << i << " tracked from row " << reference;
    }
    reference = i;
  }
  const double frame_period_s = (table.at(1, "t_ns") - table.at(0, "t_ns")) * 1e-9;
  const double longest_loss_s = r.at("tracking_states").at("lost").at("longest_run").get<double>() * frame_period_s;
  std::printf("  fastest tracked pose %.2f m/s (bound %.1f), %d frames lost, longest %.2f s, ATE %.3f m\n", fastest_mps,
              max_speed_mps, r.at("lost_frames").get<int>(), longest_loss_s, r.at("ate_rmse_m").get<double>());
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), kRoomSizeM);
  expectFramesCsvMatchesTheReport(VIFUSION_LONG_RGBD_RUN_DIR, false);
}

}  // namespace
}  // namespace vifusion
