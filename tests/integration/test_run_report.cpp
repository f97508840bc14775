// Checks the report.json files that `vifusion run` wrote for 2 s of the noisy synthetic living room (all
// three modes), the 50 real 7-Scenes frames and the wall-and-ceiling stretch of living_room_1 (ctest
// fixtures integration.run_*).

#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <nlohmann/json.hpp>

namespace vifusion {
namespace {

nlohmann::json report(const std::string& run_dir = VIFUSION_RUN_DIR, const std::string& name = "report.json") {
  std::ifstream file(run_dir + "/" + name);
  EXPECT_TRUE(file.good()) << "no " << name << " in " << run_dir;
  return nlohmann::json::parse(file);
}

TEST(RunReport, RgbdRunsTheSyntheticLivingRoomEndToEnd) {
  const nlohmann::json r = report();
  EXPECT_EQ(r.at("frames").get<int>(), 61);
  EXPECT_GT(r.at("arena_bytes").get<double>(), 0.0);
  // Frame-to-model tracking on noisy 320×240 frames (measured: 12.5 mm ATE, nothing lost over 2 s;
  // 2.1 mm over 3 s at 640×480). The bound leaves room for driver differences in float rounding.
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.025);
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
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.025);
  // states.csv against the simulator's states. 2 s at 320×240 is too short for the acceptance's 5 s /
  // 15 s windows and its estimates have not converged (measured: velocity 9.9 cm/s RMS, gravity 2.3°,
  // b_g 6e-3 rad/s at the end, ATE 16.5 mm; the first 200 frames of living_room_1 at 640×480 give
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
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.025);
  EXPECT_EQ(report(VIFUSION_GYRO_RUN_DIR, "eval.json").at("states").at("samples").get<int>(), 61);
}

// Issue 4: the wall-and-ceiling view of living_room_1 (integration.run_rgbd.living_room_1_wall_ceiling).
// The model then covers half of the view; the photometric term sampled the hole rims of the
// prediction as edges and the coarse ICP slid along the wall-ceiling edge, and the pose ran away
// (ATE 0.65 m, 0 lost). Measured after the fixes: 4.4 mm, 0 lost (seed 2: 4.3 mm).
TEST(RunReport, RgbdHoldsTheWallAndCeilingViewOfLivingRoom1) {
  const nlohmann::json r = report(VIFUSION_WALL_CEILING_RUN_DIR);
  EXPECT_EQ(r.at("frames").get<int>(), 52);
  EXPECT_EQ(r.at("lost_frames").get<int>(), 0);
  EXPECT_LT(r.at("ate_rmse_m").get<double>(), 0.015);
}

}  // namespace
}  // namespace vifusion
