#include <gtest/gtest.h>

#include <fstream>
#include <opencv2/imgcodecs.hpp>

#include "fixtures.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/seven_scenes_reader.hpp"
#include "vifusion/test/data_paths.hpp"
#include "vifusion/test/eigen_asserts.hpp"

namespace vifusion::datasets::test {
namespace {

const std::filesystem::path kRealFrames = vifusion::test::dataDir() / "7scenes-50" / "rgbd-frames";

Eigen::Matrix4d readMatrixForTest(const std::filesystem::path& path) {
  std::ifstream in(path);
  Eigen::Matrix4d m;
  for (int r = 0; r < 4; ++r) {
    for (int c = 0; c < 4; ++c) in >> m(r, c);
  }
  return m;
}

TEST(SevenScenesReader, ReadsRealFifty) {
  const std::unique_ptr<DatasetReader> reader =
      openDataset("7scenes:" + (vifusion::test::dataDir() / "7scenes-50").string());
  ASSERT_EQ(reader->frameCount(), 50u);
  const PinholeCamera& camera = reader->calibration().camera;
  EXPECT_EQ(camera.fx, 585.0);
  EXPECT_EQ(camera.cx, 320.0);
  EXPECT_EQ(camera.cy, 240.0);
  EXPECT_EQ(reader->calibration().depth_scale_m, 0.001);

  ASSERT_EQ(reader->groundTruth().size(), 50u);
  const StampedPose& first = reader->groundTruth()[0];
  EXPECT_EQ(first.t_ns, 5'000'000'000);  // frame-000150 at 150 / 30 s
  const Eigen::Matrix4d file_pose = readMatrixForTest(kRealFrames / "frame-000150.pose.txt");
  const Eigen::Vector3d file_t = file_pose.topRightCorner<3, 1>();
  const Eigen::Matrix3d file_R = file_pose.topLeftCorner<3, 3>();
  EXPECT_EQ(first.T_world_body.translation(), file_t);
  // The file's rotation is float-accumulated (off orthonormal by ~1e-4); ours is the nearest rotation.
  EXPECT_MATRIX_NEAR(first.T_world_body.rotationMatrix(), file_R, 2e-4);

  const cv::Mat depth = cv::imread((kRealFrames / "frame-000150.depth.png").string(), cv::IMREAD_ANYDEPTH);
  const cv::Mat bgr = cv::imread((kRealFrames / "frame-000150.color.png").string(), cv::IMREAD_COLOR);
  RgbdFrame frame;
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 5'000'000'000);
  EXPECT_EQ(frame.index, 0);
  for (int y = 0; y < 480; y += 7) {
    for (int x = 0; x < 640; x += 5) {
      const std::uint16_t d = depth.at<std::uint16_t>(y, x);
      ASSERT_EQ(frame.depth(x, y), d == 65535 ? 0 : d);
      const cv::Vec3b p = bgr.at<cv::Vec3b>(y, x);
      ASSERT_EQ(frame.rgb(x, y), (Rgb8{p[2], p[1], p[0]}));
    }
  }
  int delivered = 1;
  while (reader->nextFrame(frame)) ++delivered;
  EXPECT_EQ(delivered, 50);
  EXPECT_EQ(frame.t_ns, 199 * 1'000'000'000LL / 30);
  // Rewound (a looped replay's seam), the folder is delivered again from frame-000150.
  ASSERT_TRUE(reader->rewind());
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_EQ(frame.index, 0);
  EXPECT_EQ(frame.t_ns, 5'000'000'000);
  EXPECT_EQ(frame.depth(0, 0), depth.at<std::uint16_t>(0, 0) == 65535 ? 0 : depth.at<std::uint16_t>(0, 0));
}

class SevenScenesFixture : public ::testing::Test {
 protected:
  void SetUp() override {
    for (int k = 0; k < 2; ++k) {
      const std::string name = "frame-00000" + std::to_string(k);
      cv::Mat depth = depthImage(640, 480, k);
      depth.at<std::uint16_t>(3, 2) = 65535;  // 7-Scenes' invalid marker
      writePng(tmp_ / (name + ".depth.png"), depth);
      writePng(tmp_ / (name + ".color.png"), colorImageBgr(640, 480, k));
      writeText(tmp_ / (name + ".pose.txt"), "0 -1 0 1\r\n1 0 0 2\r\n0 0 1 3\r\n0 0 0 1\r\n");
    }
  }
  TempDir tmp_;
};

TEST_F(SevenScenesFixture, DecodesFramesAndMapsInvalidDepthToZero) {
  writeText(tmp_ / "camera-intrinsics.txt", "500 0 310\n0 510 230\n0 0 1\n");
  SevenScenesReader reader(tmp_.path());
  EXPECT_EQ(reader.calibration().camera.fy, 510.0);
  EXPECT_EQ(reader.calibration().camera.cx, 310.0);
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.depth(2, 3), 0);
  frame.depth(2, 3) = depthPattern(2, 3, 0);
  EXPECT_TRUE(holdsPattern(frame, 0));
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 33'333'333);
  EXPECT_FALSE(reader.nextFrame(frame));
  const SE3d& T = reader.groundTruth()[1].T_world_body;
  EXPECT_MATRIX_NEAR(T * Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(1, 3, 3), 1e-15);
}

TEST_F(SevenScenesFixture, MissingDepthIsAnError) {
  std::filesystem::remove(tmp_ / "frame-000001.depth.png");
  expectError([&] { SevenScenesReader reader(tmp_.path()); },
              "frame-000001.color.png: missing file 'frame-000001.depth.png'");
}

TEST_F(SevenScenesFixture, MissingPoseIsAnError) {
  std::filesystem::remove(tmp_ / "frame-000001.pose.txt");
  expectError([&] { SevenScenesReader reader(tmp_.path()); }, "missing file 'frame-000001.pose.txt'");
}

TEST_F(SevenScenesFixture, NaNInPoseIsAnError) {
  writeText(tmp_ / "frame-000001.pose.txt", "1 0 0 0\n0 1 0 nan\n0 0 1 0\n0 0 0 1\n");
  expectError([&] { SevenScenesReader reader(tmp_.path()); },
              "frame-000001.pose.txt line 2: column 'm24' is not a number: 'nan'");
}

TEST_F(SevenScenesFixture, NonRotationPoseIsAnError) {
  writeText(tmp_ / "frame-000000.pose.txt", "2 0 0 0\n0 1 0 0\n0 0 1 0\n0 0 0 1\n");
  expectError([&] { SevenScenesReader reader(tmp_.path()); },
              "frame-000000.pose.txt: rotation block is not a rotation matrix");
}

TEST_F(SevenScenesFixture, MissingIntrinsicsColumnIsAnError) {
  writeText(tmp_ / "camera-intrinsics.txt", "585 0 320\n0 585\n0 0 1\n");
  expectError([&] { SevenScenesReader reader(tmp_.path()); },
              "camera-intrinsics.txt line 2: expected 3 columns, found 2");
}

TEST_F(SevenScenesFixture, TruncatedDepthIsAnError) {
  truncateFile(tmp_ / "frame-000000.depth.png");
  SevenScenesReader reader(tmp_.path());
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "frame-000000.depth.png: truncated or not a PNG");
}

TEST(SevenScenesReaderErrors, EmptyFolderIsAnError) {
  TempDir tmp;
  expectError([&] { SevenScenesReader reader(tmp.path()); }, "7scenes: no frame-XXXXXX.color.png");
}

}  // namespace
}  // namespace vifusion::datasets::test
