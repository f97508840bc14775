#include <gtest/gtest.h>

#include "fixtures.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/tum_reader.hpp"
#include "vifusion/test/data_paths.hpp"

namespace vifusion::datasets::test {
namespace {

// fr1/xyz colour stamps; each depth image 5 ms before its colour image, so pairs are unambiguous.
const std::vector<std::string> kRgb = {"1305031102.175304", "1305031102.211214", "1305031102.243211"};
const std::vector<std::string> kDepth = {"1305031102.170304", "1305031102.206214", "1305031102.238211"};

class TumReaderTest : public ::testing::Test {
 protected:
  void SetUp() override { writeTumFrames(seq_, kRgb, kDepth); }
  TempDir tmp_;
  std::filesystem::path seq_ = tmp_ / "rgbd_dataset_freiburg1_xyz";
};

TEST_F(TumReaderTest, DecodesFramesExactly) {
  writeText(seq_ / "groundtruth.txt",
            "# ground truth trajectory\n1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\n"
            "1305031098.6758 1.3543 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980\n");
  writeText(seq_ / "accelerometer.txt", "# accelerometer data\n# timestamp ax ay az\n"
                                        "1305031098.6423 -0.0612 9.7964 0.7434\n1305031098.6523 -0.0459 9.8117 0.7434\n");
  TumReader reader(seq_);
  EXPECT_EQ(reader.frameCount(), 3u);
  const PinholeCamera& camera = reader.calibration().camera;
  EXPECT_EQ(camera.fx, 517.3);  // fr1 from the folder name
  EXPECT_EQ(camera.fy, 516.5);
  EXPECT_EQ(camera.cx, 318.6);
  EXPECT_EQ(camera.cy, 255.3);
  EXPECT_EQ(reader.calibration().depth_scale_m, 1.0 / 5000.0);

  RgbdFrame frame;
  for (int k = 0; k < 3; ++k) {
    ASSERT_TRUE(reader.nextFrame(frame));
    EXPECT_EQ(frame.index, k);
    EXPECT_EQ(frame.depth_scale_m, 1.0 / 5000.0);
    EXPECT_TRUE(holdsPattern(frame, k));
  }
  EXPECT_FALSE(reader.nextFrame(frame));
  ASSERT_EQ(frame.depth.width(), 640);
  EXPECT_EQ(frame.t_ns, 1305031102243211000);  // the rgb stamp, digit-exact

  ASSERT_EQ(reader.groundTruth().size(), 2u);
  EXPECT_EQ(reader.groundTruth()[0].t_ns, 1305031098665900000);
  EXPECT_EQ(reader.groundTruth()[1].T_world_body.translation(), Eigen::Vector3d(1.3543, 0.6306, 1.6360));
  ASSERT_EQ(reader.imu().size(), 2u);
  EXPECT_EQ(reader.imu()[1].t_ns, 1305031098652300000);
  EXPECT_EQ(reader.imu()[1].accel_mps2, Eigen::Vector3d(-0.0459, 9.8117, 0.7434));
  EXPECT_EQ(reader.imu()[1].gyro_rad_s, Eigen::Vector3d::Zero());  // the Kinect has no gyroscope
}

TEST_F(TumReaderTest, ReusesImageBuffers) {
  TumReader reader(seq_);
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  const std::uint16_t* depth = frame.depth.data();
  const Rgb8* rgb = frame.rgb.data();
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.depth.data(), depth);
  EXPECT_EQ(frame.rgb.data(), rgb);
}

TEST_F(TumReaderTest, AssociatesLikeAssociatePy) {
  // An extra colour image 50 ms after the last has no depth within 20 ms and is dropped; a depth image
  // 5 ms after the second colour image is closer than its own and takes it.
  writeTumFrames(seq_, {"1.000", "1.100", "1.200", "1.250"}, {"0.990", "1.105", "1.195"});
  TumReader reader(seq_);
  ASSERT_EQ(reader.frameCount(), 3u);
  RgbdFrame frame;
  std::vector<std::int64_t> stamps;
  while (reader.nextFrame(frame)) stamps.push_back(frame.t_ns);
  EXPECT_EQ(stamps, (std::vector<std::int64_t>{1'000'000'000, 1'100'000'000, 1'200'000'000}));
}

TEST_F(TumReaderTest, ReadsRealFr1XyzGroundTruth) {
  std::filesystem::copy_file(vifusion::test::dataDir() / "tum-fr1-xyz-eval" / "freiburg1_xyz-groundtruth.txt",
                             seq_ / "groundtruth.txt");
  const std::unique_ptr<DatasetReader> reader = openDataset("tum:" + seq_.string() + "/");
  EXPECT_EQ(reader->calibration().camera.fx, 517.3);  // fr1 even with a trailing slash
  ASSERT_EQ(reader->groundTruth().size(), 3000u);
  // First line: 1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986
  const StampedPose& first = reader->groundTruth()[0];
  EXPECT_EQ(first.t_ns, 1305031098665900000);
  EXPECT_EQ(first.T_world_body.translation(), Eigen::Vector3d(1.3563, 0.6305, 1.6380));
  const Eigen::Quaterniond q = Eigen::Quaterniond(-0.3986, 0.6132, 0.5962, -0.3311).normalized();
  EXPECT_LT(first.T_world_body.quaternion().angularDistance(q), 1e-12);
}

TEST(TumReaderIntrinsics, ChoosesByFolderName) {
  EXPECT_EQ(TumReader::intrinsicsForFolder("rgbd_dataset_freiburg2_desk").fx, 520.9);
  EXPECT_EQ(TumReader::intrinsicsForFolder("fr3_office").cy, 247.6);
  const PinholeCamera other = TumReader::intrinsicsForFolder("my_kinect");
  EXPECT_EQ(other.fx, 525.0);
  EXPECT_EQ(other.cx, 319.5);
  EXPECT_EQ(other.width, 640);
}

TEST_F(TumReaderTest, TruncatedPngIsAnErrorNamingTheFile) {
  truncateFile(seq_ / "depth" / "1305031102.206214.png");
  TumReader reader(seq_);
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  expectError([&] { reader.nextFrame(frame); }, "depth/1305031102.206214.png: truncated or not a PNG");
}

TEST_F(TumReaderTest, NonPngBytesAreAnError) {
  writeText(seq_ / "rgb" / "1305031102.175304.png", "not an image at all");
  TumReader reader(seq_);
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "rgb/1305031102.175304.png: truncated or not a PNG");
}

TEST_F(TumReaderTest, MissingImageIsAnErrorAtOpen) {
  std::filesystem::remove(seq_ / "rgb" / "1305031102.243211.png");
  expectError([&] { TumReader reader(seq_); }, "rgb.txt line 5: missing file 'rgb/1305031102.243211.png'");
}

TEST_F(TumReaderTest, MissingIndexFileIsAnError) {
  std::filesystem::remove(seq_ / "depth.txt");
  expectError([&] { TumReader reader(seq_); }, "depth.txt: cannot open file");
}

TEST_F(TumReaderTest, TimeGoingBackwardsIsAnError) {
  writeText(seq_ / "rgb.txt", "1305031102.211214 rgb/1305031102.211214.png\n"
                              "1305031102.175304 rgb/1305031102.175304.png\n");
  expectError([&] { TumReader reader(seq_); }, "rgb.txt line 2: timestamp goes backwards by 35.91 ms");
}

TEST_F(TumReaderTest, MissingColumnIsAnError) {
  writeText(seq_ / "depth.txt", "1305031102.170304 depth/1305031102.170304.png\n1305031102.206214\n");
  expectError([&] { TumReader reader(seq_); }, "depth.txt line 2: expected 2 columns 'timestamp filename', found 1");
}

TEST_F(TumReaderTest, BadTimestampIsAnError) {
  writeText(seq_ / "depth.txt", "1305031102.16O407 depth/1305031102.170304.png\n");
  expectError([&] { TumReader reader(seq_); }, "depth.txt line 1: field 'timestamp' is not a timestamp in seconds");
}

TEST_F(TumReaderTest, NaNInGroundTruthIsAnError) {
  writeText(seq_ / "groundtruth.txt", "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 -0.3986\n"
                                      "1305031098.6758 nan 0.6306 1.6360 0.6129 0.5966 -0.3316 -0.3980\n");
  expectError([&] { TumReader reader(seq_); }, "groundtruth.txt line 2: column 'tx' is not a number: 'nan'");
}

TEST_F(TumReaderTest, BadQuaternionInGroundTruthIsAnError) {
  writeText(seq_ / "groundtruth.txt", "1305031098.6659 1.3563 0.6305 1.6380 0.6132 0.5962 -0.3311 0.3986\n"
                                      "1305031098.6758 1 2 3 0 0 0 2\n");
  expectError([&] { TumReader reader(seq_); }, "groundtruth.txt line 2: quaternion norm 2 is more than 0.001 from 1");
}

TEST_F(TumReaderTest, NaNInAccelerometerIsAnError) {
  writeText(seq_ / "accelerometer.txt", "1305031098.6423 -0.0612 9.7964 0.7434\n1305031098.6523 -0.0459 nan 0.7434\n");
  expectError([&] { TumReader reader(seq_); }, "accelerometer.txt line 2: column 'ay' is not a number: 'nan'");
}

TEST_F(TumReaderTest, WrongImageSizeIsAnError) {
  writePng(seq_ / "rgb" / "1305031102.211214.png", colorImageBgr(320, 240, 0));
  TumReader reader(seq_);
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  expectError([&] { reader.nextFrame(frame); }, "rgb/1305031102.211214.png: image is 320x240, expected 640x480");
}

TEST_F(TumReaderTest, WrongDepthTypeIsAnError) {
  writePng(seq_ / "depth" / "1305031102.170304.png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(7)));
  TumReader reader(seq_);
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); },
              "depth/1305031102.170304.png: depth must be a 16-bit 1-channel image, found 8-bit 1-channel");
}

TEST_F(TumReaderTest, NoAssociationIsAnError) {
  writeTumFrames(seq_, {"1.000"}, {"1.500"});
  expectError([&] { TumReader reader(seq_); }, "no rgb.txt entry has a depth.txt entry within 20 ms");
}

TEST_F(TumReaderTest, OpensThroughSpec) {
  const std::unique_ptr<DatasetReader> reader = openDataset("tum:" + seq_.string());
  EXPECT_EQ(reader->frameCount(), 3u);
  EXPECT_NE(reader->describe().find("TUM RGB-D"), std::string::npos);
}

}  // namespace
}  // namespace vifusion::datasets::test
