// End to end through files: a dataset written by `vifusion sim` (ctest fixture, noise-free) read
// back with the datasets library must be internally consistent: the camera ground truth equals the
// IMU ground truth composed with the calibration's T_S_C, every depth pixel back-projects onto the
// analytic scene, and the accelerometer reads gravity plus the spline's acceleration.

#include <gtest/gtest.h>

#include <algorithm>

#include "vifusion/core/error.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/scene/living_room.hpp"

namespace vifusion {
namespace {

// Written by the ctest fixture integration.sim_dataset.write before these tests run.
std::string datasetDir() { return VIFUSION_SIM_DATASET; }

TEST(SimDataset, ReadsBackWithConsistentGroundTruthAndCalibration) {
  const auto reader = datasets::openDataset("dataset:" + datasetDir());
  const RigCalibration& calibration = reader->calibration();
  EXPECT_EQ(calibration.camera.width, 160);
  EXPECT_EQ(calibration.imu.rate_hz, 200.0);
  EXPECT_EQ(calibration.inverse_depth_bias_per_m, 0.0);  // noise-free depth has no bias to remove
  EXPECT_EQ(reader->frameCount(), 31u);                  // 1 s at 30 Hz, both ends included
  ASSERT_EQ(reader->groundTruth().size(), reader->frameCount());
  ASSERT_GE(reader->imu().size(), 200u);
  ASSERT_EQ(reader->groundTruthStates().size(), reader->imu().size());

  // Camera ground truth = IMU ground truth · T_S_C (states interpolated at the frame time).
  const auto states = reader->groundTruthStates();
  for (const datasets::StampedPose& pose : reader->groundTruth()) {
    const auto after = std::lower_bound(states.begin(), states.end(), pose.t_ns,
                                        [](const GroundTruthState& s, int64_t t) { return s.t_ns < t; });
    ASSERT_NE(after, states.end());
    if (after->t_ns != pose.t_ns) continue;  // frames fall on IMU samples every 100 ms
    const SE3d T_W_S(after->q_W_S, after->p_W_S);
    const SE3d T_W_C = T_W_S * calibration.T_S_C;
    EXPECT_LT((T_W_C.translation() - pose.T_world_body.translation()).norm(), 1e-6);
    EXPECT_LT(T_W_C.quaternion().angularDistance(pose.T_world_body.quaternion()), 1e-6);
  }
}

TEST(SimDataset, NoiseFreeDepthLiesOnTheSceneSurface) {
  const auto reader = datasets::openDataset("dataset:" + datasetDir());
  const RigCalibration& calibration = reader->calibration();
  const scene::LivingRoom room;
  RgbdFrame frame;
  std::size_t index = 0;
  while (reader->nextFrame(frame)) {
    const SE3d& T_W_C = reader->groundTruth()[index++].T_world_body;
    double worst_m = 0.0;
    int valid = 0;
    for (int v = 0; v < frame.depth.height(); v += 3) {
      for (int u = 0; u < frame.depth.width(); u += 3) {
        if (frame.depth(u, v) == 0) continue;
        const double z_m = frame.depth(u, v) * frame.depth_scale_m;
        const Eigen::Vector3d p_W = T_W_C * calibration.camera.backProject(Eigen::Vector2d(u, v), z_m);
        worst_m = std::max(worst_m, room.distanceToSurface(p_W));
        ++valid;
      }
    }
    EXPECT_GT(valid, 1000);
    // 16-bit depth at 5000 per metre: 0.1 mm quantisation, grazing views stretch it a little.
    EXPECT_LT(worst_m, 1e-3) << "frame " << index;
  }
}

// `vifusion sim --cover 0.41 0.3`: the frames from 0.41 s to 0.71 s after the first are black with no depth (a hand
// over the lens), every other frame is the uncovered dataset's byte for byte, and the IMU and the ground truth go
// on as if nothing happened.
TEST(SimDataset, CoveredFramesAreBlankAndEverythingElseIsUnchanged) {
  const auto covered = datasets::openDataset(std::string("dataset:") + VIFUSION_SIM_COVERED_DATASET);
  const auto uncovered = datasets::openDataset("dataset:" + datasetDir());
  ASSERT_EQ(covered->frameCount(), uncovered->frameCount());
  ASSERT_EQ(covered->imu().size(), uncovered->imu().size());
  for (std::size_t i = 0; i < covered->imu().size(); ++i) {
    ASSERT_EQ(covered->imu()[i].t_ns, uncovered->imu()[i].t_ns);
    ASSERT_EQ(covered->imu()[i].gyro_rad_s, uncovered->imu()[i].gyro_rad_s);
  }
  RgbdFrame a, b;
  int blank = 0;
  while (covered->nextFrame(a) && uncovered->nextFrame(b)) {
    ASSERT_EQ(a.t_ns, b.t_ns);
    const double t_s = static_cast<double>(a.t_ns - covered->groundTruth().front().t_ns) * 1e-9;
    const bool in_cover = t_s >= 0.41 && t_s < 0.71;  // no frame within 1 µs of either end
    const bool a_blank =
        std::all_of(a.depth.data(), a.depth.data() + a.depth.pixelCount(), [](auto d) { return d == 0; }) &&
        std::all_of(a.rgb.data(), a.rgb.data() + a.rgb.pixelCount(), [](const Rgb8& c) { return c == Rgb8{}; });
    EXPECT_EQ(a_blank, in_cover) << "frame " << a.index << " at " << t_s << " s";
    if (!in_cover) {
      EXPECT_TRUE(std::equal(a.depth.data(), a.depth.data() + a.depth.pixelCount(), b.depth.data())) << a.index;
    }
    blank += a_blank ? 1 : 0;
  }
  EXPECT_EQ(blank, 9);  // frames 13–21 (0.433–0.700 s)
}

TEST(SimDataset, NoiseFreeImuMatchesTheGroundTruthMotion) {
  // Specific force R_W_Sᵀ(a_W − g_W) + b_a and rate ω_S + b_g, with a_W and ω_S taken by central
  // differences of the true velocities and orientations 5 ms apart (truncation ≈ 1e-4).
  const auto reader = datasets::openDataset("dataset:" + datasetDir());
  const auto states = reader->groundTruthStates();
  const auto samples = reader->imu();
  for (std::size_t k = 1; k + 1 < states.size(); k += 20) {
    const double dt_s = 1e-9 * static_cast<double>(states[k + 1].t_ns - states[k - 1].t_ns);
    const Eigen::Vector3d a_W = (states[k + 1].v_W_S - states[k - 1].v_W_S) / dt_s;
    const Eigen::AngleAxisd rotation(states[k - 1].q_W_S.conjugate() * states[k + 1].q_W_S);
    const Eigen::Vector3d omega_S =
        states[k].q_W_S.conjugate() * states[k - 1].q_W_S * (rotation.angle() / dt_s * rotation.axis());
    const Eigen::Vector3d expected_accel =
        states[k].q_W_S.conjugate() * (a_W - reader->calibration().g_W) + states[k].b_a;
    EXPECT_LT((samples[k].accel_mps2 - expected_accel).norm(), 2e-3) << "sample " << k;
    EXPECT_LT((samples[k].gyro_rad_s - (omega_S + states[k].b_g)).norm(), 2e-3) << "sample " << k;
  }
}

}  // namespace
}  // namespace vifusion
