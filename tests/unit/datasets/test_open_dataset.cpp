#include <gtest/gtest.h>

#include "fixtures.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/euroc_imu.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/datasets/kalibr.hpp"
#include "vifusion/datasets/recalibrated_reader.hpp"
#include "vifusion/datasets/vifusion_dataset_reader.hpp"

namespace vifusion::datasets::test {
namespace {

TEST(OpenDataset, UnknownPrefixListsTheValidOnes) {
  expectError(
      [] { openDataset("euroc:/data/V1_01"); },
      "unknown dataset source 'euroc:/data/V1_01'; valid: tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE, dataset:DIR");
  expectError([] { openDataset("/just/a/path"); }, "unknown dataset source '/just/a/path'");
  expectError([] { openDataset("tum:"); }, "no path after 'tum:'");
}

TEST(OpenDataset, CliSourcesAreReferredToTheCli) {
  expectError([] { openDataset("sim:living_room_0"); }, "'sim' is opened by the vifusion CLI");
  expectError([] { openDataset("zr300"); }, "'zr300' is opened by the vifusion CLI");
}

TEST(OpenDataset, MissingDirectoryIsAnError) {
  expectError([] { openDataset("tum:/nonexistent/vifusion"); }, "tum: '/nonexistent/vifusion' is not a directory");
  expectError([] { openDataset("dataset:/nonexistent/vifusion"); }, "is not a directory");
}

/// A small dataset directory as `vifusion sim` writes it: 160×120 frames, calibration.yaml, imu.csv,
/// groundtruth.txt and groundtruth_states.csv.
class VifusionDatasetTest : public ::testing::Test {
 protected:
  void SetUp() override {
    writeTumFrames(tmp_.path(), {"0.000000000", "0.033333333"}, {"0.000000000", "0.033333333"}, 160, 120);
    calibration_.camera = PinholeCamera::create(160, 120, 120.3, 120.3, 79.5, 59.5);
    calibration_.T_S_C = SE3d(Eigen::Quaterniond(0.5, 0.5, -0.5, 0.5), Eigen::Vector3d(0.01, 0.02, 0.03));
    writeCalibrationYaml(tmp_ / "calibration.yaml", calibration_);
    std::vector<ImuSample> imu(7);
    std::vector<GroundTruthState> states(7);
    for (std::size_t k = 0; k < imu.size(); ++k) {
      imu[k].t_ns = static_cast<std::int64_t>(k) * 5'000'000;
      imu[k].accel_mps2 = Eigen::Vector3d(0.0, 9.81, 0.001 * static_cast<double>(k));
      states[k].t_ns = imu[k].t_ns;
      states[k].p_W_S.x() = 0.01 * static_cast<double>(k);
    }
    writeEurocImu(tmp_ / "imu.csv", imu);
    writeGroundTruthStates(tmp_ / "groundtruth_states.csv", states);
    writeText(tmp_ / "groundtruth.txt", "# timestamp tx ty tz qx qy qz qw\n0.000000000 1 2 3 0 0 0 1\n");
  }
  TempDir tmp_;
  RigCalibration calibration_;
};

TEST_F(VifusionDatasetTest, ReadsEverything) {
  const std::unique_ptr<DatasetReader> reader = openDataset("dataset:" + tmp_.path().string());
  EXPECT_EQ(reader->calibration().camera.fx, 120.3);
  EXPECT_TRUE(reader->calibration().T_S_C.matrix().isApprox(calibration_.T_S_C.matrix(), 1e-15));
  ASSERT_EQ(reader->frameCount(), 2u);
  RgbdFrame frame;
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_TRUE(holdsPattern(frame, 0));
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 33'333'333);
  EXPECT_EQ(frame.depth.width(), 160);
  EXPECT_TRUE(holdsPattern(frame, 1));
  EXPECT_FALSE(reader->nextFrame(frame));
  ASSERT_EQ(reader->imu().size(), 7u);
  EXPECT_EQ(reader->imu()[6].accel_mps2.z(), 0.006);
  ASSERT_EQ(reader->groundTruthStates().size(), 7u);
  EXPECT_EQ(reader->groundTruthStates()[3].p_W_S.x(), 0.03);
  ASSERT_EQ(reader->groundTruth().size(), 1u);
  EXPECT_EQ(reader->groundTruth()[0].T_world_body.translation(), Eigen::Vector3d(1, 2, 3));
}

TEST_F(VifusionDatasetTest, ImagesMustMatchTheCalibratedResolution) {
  writePng(tmp_ / "depth" / "0.033333333.png", depthImage(640, 480, 1));
  VifusionDatasetReader reader(tmp_.path());
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  expectError([&] { reader.nextFrame(frame); }, "depth/0.033333333.png: image is 640x480, expected 160x120");
}

TEST_F(VifusionDatasetTest, AnUnreadableFrameIsPassedSoTheNextOneCanBeRead) {
  writeText(tmp_ / "depth" / "0.000000000.png", "\x89PNG truncated");
  VifusionDatasetReader reader(tmp_.path());
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "depth/0.000000000.png");
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.index, 1);
  EXPECT_TRUE(holdsPattern(frame, 1));
  EXPECT_FALSE(reader.nextFrame(frame));
}

TEST_F(VifusionDatasetTest, ImuIsRequired) {
  std::filesystem::remove(tmp_ / "imu.csv");
  expectError([&] { VifusionDatasetReader reader(tmp_.path()); }, "imu.csv: cannot open file");
}

TEST_F(VifusionDatasetTest, CalibrationIsRequired) {
  std::filesystem::remove(tmp_ / "calibration.yaml");
  expectError([&] { VifusionDatasetReader reader(tmp_.path()); }, "calibration.yaml: cannot open file");
}

TEST_F(VifusionDatasetTest, ARigCalibrationReplacesTheRecordingsOwn) {
  RigCalibration rig = calibration_;
  rig.inverse_depth_bias_per_m = 1.5e-3;
  rig.camera.fx = 121.0;
  const std::unique_ptr<DatasetReader> reader =
      withCalibration(openDataset("dataset:" + tmp_.path().string()), rig, "rig.yaml");
  EXPECT_EQ(reader->calibration().inverse_depth_bias_per_m, 1.5e-3);
  EXPECT_EQ(reader->calibration().camera.fx, 121.0);
  EXPECT_NE(reader->describe().find("calibration from rig.yaml in place of its own"), std::string::npos)
      << reader->describe();
  // Frames, IMU and ground truth are the recording's.
  ASSERT_EQ(reader->frameCount(), 2u);
  RgbdFrame frame;
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_TRUE(holdsPattern(frame, 0));
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_TRUE(holdsPattern(frame, 1));
  EXPECT_FALSE(reader->nextFrame(frame));
  EXPECT_EQ(reader->imu().size(), 7u);
  EXPECT_EQ(reader->groundTruth().size(), 1u);
  EXPECT_EQ(reader->groundTruthStates().size(), 7u);
}

TEST_F(VifusionDatasetTest, ARigCalibrationMustDescribeTheSameImages) {
  RigCalibration other_size = calibration_;
  other_size.camera = PinholeCamera::create(320, 240, 240.6, 240.6, 159.5, 119.5);
  expectError([&] { withCalibration(openDataset("dataset:" + tmp_.path().string()), other_size, "rig.yaml"); },
              "rig.yaml: its camera is 320×240 px but the recording's images are 160×120 px");
  RigCalibration other_units = calibration_;
  other_units.depth_scale_m = 1e-3;
  expectError([&] { withCalibration(openDataset("dataset:" + tmp_.path().string()), other_units, "rig.yaml"); },
              "rig.yaml: depth_scale_m 0.001 m per unit differs from the recording's 0.0002");
}

}  // namespace
}  // namespace vifusion::datasets::test
