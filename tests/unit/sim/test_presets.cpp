#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <string>

#include "sim_test_utils.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/sim/imu_simulator.hpp"
#include "vifusion/sim/presets.hpp"
#include "vifusion/sim/trajectory_fit.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::sim {
namespace {

/// Peak figures of a preset's fitted spline, from an ideal 200 Hz IMU and the spline's camera poses.
struct PresetFigures {
  double duration_s = 0.0;
  double path_length_m = 0.0;
  double peak_speed_mps = 0.0;
  double peak_rate_rad_s = 0.0;
  double peak_gyro_axis_rad_s = 0.0;
  double peak_accel_axis_mps2 = 0.0;
  Eigen::Vector3d min_p_W_C = Eigen::Vector3d::Constant(1e9);
  Eigen::Vector3d max_p_W_C = Eigen::Vector3d::Constant(-1e9);
  double min_horizontal_view = 1.0;  ///< smallest horizontal share of the viewing direction, √(1 − z_y²)
};

PresetFigures measure(std::string_view name) {
  TrajectoryFitOptions fit_options;
  fit_options.subsample = presetTraits(name).fit_subsample;
  const TrajectoryFit fit = fitTrajectory(presetCameraPoses(name), test::exampleT_S_C(), fit_options);
  ImuSimOptions options;
  options.add_noise = false;
  options.add_biases = false;
  const ImuSimResult imu = simulateImu(fit.spline_W_S, options);
  PresetFigures f;
  f.duration_s = nsToSeconds(fit.spline_W_S.endTimeNs() - fit.spline_W_S.startTimeNs());
  Eigen::Vector3d previous = imu.states.front().p_W_S;
  for (std::size_t k = 0; k < imu.samples.size(); ++k) {
    const GroundTruthState& s = imu.states[k];
    f.path_length_m += (s.p_W_S - previous).norm();
    previous = s.p_W_S;
    f.peak_speed_mps = std::max(f.peak_speed_mps, s.v_W_S.norm());
    f.peak_rate_rad_s = std::max(f.peak_rate_rad_s, imu.samples[k].gyro_rad_s.norm());
    f.peak_gyro_axis_rad_s = std::max(f.peak_gyro_axis_rad_s, imu.samples[k].gyro_rad_s.cwiseAbs().maxCoeff());
    f.peak_accel_axis_mps2 = std::max(f.peak_accel_axis_mps2, imu.samples[k].accel_mps2.cwiseAbs().maxCoeff());
    const SE3d T_W_C = fit.cameraPose(s.t_ns);
    f.min_p_W_C = f.min_p_W_C.cwiseMin(T_W_C.translation());
    f.max_p_W_C = f.max_p_W_C.cwiseMax(T_W_C.translation());
    const double up_share = (T_W_C.quaternion() * Eigen::Vector3d::UnitZ()).y();
    f.min_horizontal_view = std::min(f.min_horizontal_view, std::sqrt(1.0 - up_share * up_share));
  }
  std::printf(
      "%-15s %4.0f s, %5.2f m, peak %.2f m/s, %.2f rad/s (axis %.2f), accel axis %.2f m/s², "
      "camera x [%.2f, %.2f] y [%.2f, %.2f] z [%.2f, %.2f]\n",
      std::string(name).c_str(), f.duration_s, f.path_length_m, f.peak_speed_mps, f.peak_rate_rad_s,
      f.peak_gyro_axis_rad_s, f.peak_accel_axis_mps2, f.min_p_W_C.x(), f.max_p_W_C.x(), f.min_p_W_C.y(),
      f.max_p_W_C.y(), f.min_p_W_C.z(), f.max_p_W_C.z());
  EXPECT_EQ(imu.gyro_clipped_samples, 0) << name;
  EXPECT_EQ(imu.accel_clipped_samples, 0) << name;
  return f;
}

void expectInsideIclNuimBox(const PresetFigures& f, std::string_view name) {
  EXPECT_GE(f.min_p_W_C.x(), -0.1) << name;
  EXPECT_LE(f.max_p_W_C.x(), 2.3) << name;
  EXPECT_GE(f.min_p_W_C.y(), 0.5) << name;
  EXPECT_LE(f.max_p_W_C.y(), 1.8) << name;
  EXPECT_GE(f.min_p_W_C.z(), -1.9) << name;
  EXPECT_LE(f.max_p_W_C.z(), 1.6) << name;
  EXPECT_GT(f.min_horizontal_view, 0.9) << name << ": the camera should look mostly horizontally";
}

TEST(Presets, FastIsHandHeldFast) {
  const PresetFigures f = measure("fast");
  expectInsideIclNuimBox(f, "fast");
  EXPECT_NEAR(f.duration_s, 20.0, 1e-6);
  EXPECT_GT(f.peak_speed_mps, 1.5);
  EXPECT_LT(f.peak_speed_mps, 2.2);
  EXPECT_GT(f.peak_rate_rad_s, 2.5);
  EXPECT_LT(f.peak_rate_rad_s, 3.5);
}

TEST(Presets, QuickRotationPansFastBelowSaturation) {
  const PresetFigures f = measure("quick_rotation");
  expectInsideIclNuimBox(f, "quick_rotation");
  EXPECT_GT(f.peak_rate_rad_s, 4.0);
  EXPECT_LT(f.peak_rate_rad_s, 6.0);
  EXPECT_LT(f.peak_gyro_axis_rad_s, 7.8 * 0.8);  // margin for other extrinsics
  EXPECT_LT(f.peak_speed_mps, 0.5);
}

TEST(Presets, WhiteWallTurnsFromTheRoomToTheBlankWallAndBack) {
  const PresetFigures f = measure("white_wall");
  expectInsideIclNuimBox(f, "white_wall");
  EXPECT_NEAR(f.duration_s, 20.0, 1e-6);
  EXPECT_LT(f.peak_speed_mps, 0.4);  // a slow walk; the turns are head turns
  EXPECT_LT(f.peak_rate_rad_s, 2.0);
  // Longest stretch facing the wall from ≈ 1.6 m (it fills the view), and the room seen before and after.
  double facing_s = 0.0, longest_facing_s = 0.0, first_wall_s = -1.0, last_wall_s = -1.0;
  const std::vector<StampedPose> poses = presetCameraPoses("white_wall");
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d forward_W = pose.T_world_body.quaternion() * Eigen::Vector3d::UnitZ();
    const double t_s = nsToSeconds(pose.t_ns);
    const bool facing = forward_W.x() > 0.98 && pose.T_world_body.translation().x() > 2.15;
    facing_s = facing ? facing_s + 1.0 / kPresetFrameRateHz : 0.0;
    longest_facing_s = std::max(longest_facing_s, facing_s);
    if (forward_W.x() > 0.5) {
      if (first_wall_s < 0.0) first_wall_s = t_s;
      last_wall_s = t_s;
    }
  }
  EXPECT_GT(longest_facing_s, 2.5);
  EXPECT_LT(last_wall_s - first_wall_s, 6.0) << "a pass along the wall, not a stay";
  EXPECT_GT(first_wall_s, 5.0) << "the room comes first, so the biases converge";
  EXPECT_LT(last_wall_s, 14.0) << "the room comes back, so the map is seen again";
}

TEST(Presets, LongIsAClosedLoopAroundTheRoom) {
  const PresetFigures f = measure("long");
  expectInsideIclNuimBox(f, "long");
  EXPECT_NEAR(f.duration_s, 60.0, 1e-6);
  EXPECT_GT(f.path_length_m, 15.0);
  EXPECT_LT(f.path_length_m, 20.0);
  EXPECT_LT(f.peak_speed_mps, 0.6);
  const std::vector<StampedPose> poses = presetCameraPoses("long");
  EXPECT_MATRIX_NEAR(poses.front().T_world_body.matrix(), poses.back().T_world_body.matrix(), 1e-9);
}

TEST(Presets, UnmappedTurnTurnsHalfRoundIntoWhatItHasNotSeen) {
  const PresetFigures f = measure("unmapped_turn");
  expectInsideIclNuimBox(f, "unmapped_turn");
  EXPECT_NEAR(f.duration_s, 16.0, 1e-6);
  EXPECT_GT(f.peak_rate_rad_s, 3.5);
  EXPECT_LT(f.peak_gyro_axis_rad_s, 7.8 * 0.8);
  EXPECT_LT(f.peak_speed_mps, 0.4);
  // Looking north (−z) before the turn, south after it, and the turn itself short.
  double turn_start_s = -1.0, turn_end_s = -1.0;
  for (const StampedPose& pose : presetCameraPoses("unmapped_turn")) {
    const double forward_z = (pose.T_world_body.quaternion() * Eigen::Vector3d::UnitZ()).z();
    const double t_s = nsToSeconds(pose.t_ns);
    if (turn_start_s < 0.0 && forward_z > -0.85) turn_start_s = t_s;
    if (turn_end_s < 0.0 && forward_z > 0.85) turn_end_s = t_s;
  }
  EXPECT_GT(turn_start_s, 6.0) << "the north half is mapped first";
  EXPECT_LT(turn_end_s - turn_start_s, 1.2) << "a quick turn";
  EXPECT_LT(turn_end_s, 9.0) << "and a long stretch in the south half after it";
}

TEST(Presets, FastPanLeavesTheFirstViewAtOnce) {
  const PresetFigures f = measure("fast_pan");
  expectInsideIclNuimBox(f, "fast_pan");
  EXPECT_NEAR(f.duration_s, 14.0, 1e-6);
  EXPECT_GT(f.peak_rate_rad_s, 2.4);
  EXPECT_LT(f.peak_speed_mps, 0.25) << "standing: only the hand sways";
  // 90° away from the first view within 1.2 s of the start.
  const std::vector<StampedPose> poses = presetCameraPoses("fast_pan");
  const Eigen::Vector3d first_W = poses.front().T_world_body.quaternion() * Eigen::Vector3d::UnitZ();
  double quarter_turn_s = -1.0;
  for (const StampedPose& pose : poses) {
    if ((pose.T_world_body.quaternion() * Eigen::Vector3d::UnitZ()).dot(first_W) < 0.0) {
      quarter_turn_s = nsToSeconds(pose.t_ns);
      break;
    }
  }
  EXPECT_GT(quarter_turn_s, 0.0);
  EXPECT_LT(quarter_turn_s, 1.2);
}

TEST(Presets, RevisitComesBackToItsFirstViewLongAfterTheTimeWindow) {
  const PresetFigures f = measure("revisit");
  expectInsideIclNuimBox(f, "revisit");
  EXPECT_NEAR(f.duration_s, 35.0, 1e-6);
  EXPECT_LT(f.peak_speed_mps, 0.5);
  EXPECT_LT(f.peak_rate_rad_s, 3.0);
  // The third leg passes the first view again; both turns keep away from the plain x-max wall.
  const std::vector<StampedPose> poses = presetCameraPoses("revisit");
  const SE3d first = poses.front().T_world_body;
  double left_first_view_s = 0.0, back_at_first_view_s = -1.0, most_east = -1.0;
  for (const StampedPose& pose : poses) {
    const Eigen::Vector3d forward_W = pose.T_world_body.quaternion() * Eigen::Vector3d::UnitZ();
    most_east = std::max(most_east, forward_W.x());
    const bool near_first = (pose.T_world_body.translation() - first.translation()).norm() < 0.2 &&
                            pose.T_world_body.quaternion().angularDistance(first.quaternion()) < 0.3;
    const double t_s = nsToSeconds(pose.t_ns);
    if (near_first && t_s < 15.0) left_first_view_s = t_s;
    if (near_first && t_s > 15.0 && back_at_first_view_s < 0.0) back_at_first_view_s = t_s;
  }
  EXPECT_LT(most_east, 0.3) << "never looks at the plain wall";
  // The map's time window is 200 frames (6.7 s at 30 Hz): the first view is left within seconds and seen
  // again far beyond the window.
  EXPECT_LT(left_first_view_s, 5.0);
  EXPECT_GT(back_at_first_view_s, 20.0);
  EXPECT_LT(back_at_first_view_s, 30.0);
}

TEST(Presets, AllStartAndEndAtRestAt30Hz) {
  // At rest: the first and last frame periods move less than 20 µm (0.6 mm/s; fast_pan's 0.4 s ramp moves
  // 4 µm, the others' 2.5–3 s ramps < 1 µm).
  constexpr double kAtRestStepM = 2e-5;
  for (const std::string_view name : presetNames()) {
    const std::vector<StampedPose> poses = presetCameraPoses(name);
    EXPECT_EQ(poses[1].t_ns, 33'333'333) << name;
    EXPECT_EQ(poses[3].t_ns, 100'000'000) << name;
    EXPECT_LT((poses[1].T_world_body.translation() - poses[0].T_world_body.translation()).norm(), kAtRestStepM) << name;
    const std::size_t n = poses.size();
    EXPECT_LT((poses[n - 1].T_world_body.translation() - poses[n - 2].T_world_body.translation()).norm(), kAtRestStepM)
        << name;
  }
  EXPECT_THROW(presetCameraPoses("slow"), Error);
}

}  // namespace
}  // namespace vifusion::sim
