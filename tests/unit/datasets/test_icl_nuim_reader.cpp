#include <gtest/gtest.h>

#include "fixtures.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/icl_nuim_reader.hpp"

namespace vifusion::datasets::test {
namespace {

class IclNuimReaderTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string associations;
    for (int k = 0; k < 2; ++k) {
      const std::string n = std::to_string(k);
      writePng(seq_ / "rgb" / (n + ".png"), colorImageBgr(640, 480, k));
      writePng(seq_ / "depth" / (n + ".png"), depthImage(640, 480, k));
      associations += n + " depth/" + n + ".png " + n + " rgb/" + n + ".png\n";
    }
    writeText(seq_ / "associations.txt", associations);
  }
  TempDir tmp_;
  std::filesystem::path seq_ = tmp_ / "living_room_traj0_frei_png";
};

TEST_F(IclNuimReaderTest, DecodesFramesWithIclIntrinsicsAndIndexStamps) {
  writeText(seq_ / "livingRoom0.gt.freiburg", "0 0 0 -2.25 0 0 0 1\n1 0.000790 0.020016 -2.257000 0 0 0 1\n");
  IclNuimReader reader(seq_);
  const PinholeCamera& camera = reader.calibration().camera;
  EXPECT_EQ(camera.fx, 481.20);
  EXPECT_EQ(camera.fy, -480.00);
  EXPECT_EQ(camera.cx, 319.5);
  EXPECT_EQ(camera.cy, 239.5);
  EXPECT_EQ(reader.calibration().depth_scale_m, 1.0 / 5000.0);
  ASSERT_EQ(reader.frameCount(), 2u);
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 0);
  EXPECT_TRUE(holdsPattern(frame, 0));
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 33'333'333);  // frame 1 of a 30 Hz render
  EXPECT_TRUE(holdsPattern(frame, 1));
  EXPECT_FALSE(reader.nextFrame(frame));
  ASSERT_EQ(reader.groundTruth().size(), 2u);
  EXPECT_EQ(reader.groundTruth()[1].t_ns, 33'333'333);
  EXPECT_EQ(reader.groundTruth()[1].T_world_body.translation(), Eigen::Vector3d(0.000790, 0.020016, -2.257000));
}

TEST_F(IclNuimReaderTest, MissingColumnIsAnError) {
  writeText(seq_ / "associations.txt", "0 depth/0.png 0 rgb/0.png\n1 depth/1.png 1\n");
  expectError([&] { IclNuimReader reader(seq_); },
              "associations.txt line 2: expected 4 columns 't_depth depth_file t_rgb rgb_file', found 3");
}

TEST_F(IclNuimReaderTest, MissingFileIsAnError) {
  std::filesystem::remove(seq_ / "depth" / "1.png");
  expectError([&] { IclNuimReader reader(seq_); }, "associations.txt line 2: missing file 'depth/1.png'");
}

TEST_F(IclNuimReaderTest, TimeGoingBackwardsIsAnError) {
  writeText(seq_ / "associations.txt", "1 depth/1.png 1 rgb/1.png\n0 depth/0.png 0 rgb/0.png\n");
  expectError([&] { IclNuimReader reader(seq_); }, "associations.txt line 2: timestamp goes backwards by 33.3333 ms");
}

TEST_F(IclNuimReaderTest, TwoGroundTruthFilesAreAnError) {
  writeText(seq_ / "a.gt.freiburg", "0 0 0 0 0 0 0 1\n");
  writeText(seq_ / "b.gt.freiburg", "0 0 0 0 0 0 0 1\n");
  expectError([&] { IclNuimReader reader(seq_); }, "2 *.gt.freiburg files");
}

TEST_F(IclNuimReaderTest, TruncatedPngIsAnError) {
  truncateFile(seq_ / "rgb" / "0.png");
  const std::unique_ptr<DatasetReader> reader = openDataset("icl:" + seq_.string());
  RgbdFrame frame;
  expectError([&] { reader->nextFrame(frame); }, "rgb/0.png: truncated or not a PNG");
}

}  // namespace
}  // namespace vifusion::datasets::test
