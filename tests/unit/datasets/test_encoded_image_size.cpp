// encodedImageSize against OpenCV's own encoders (PNG 8/16-bit, baseline and progressive JPEG), on cut and
// foreign bytes; and the readers refusing a header of the wrong size before decoding (found by
// fuzz_image_files: a 2 kB PNG could declare 30000×30000 and OpenCV would allocate it).

#include <gtest/gtest.h>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "encoded_image_size.hpp"
#include "fixtures.hpp"
#include "vifusion/datasets/seven_scenes_reader.hpp"

namespace vifusion::datasets::test {
namespace {

using detail::encodedImageSize;

std::vector<std::uint8_t> encoded(const char* extension, const cv::Mat& image, const std::vector<int>& params = {}) {
  std::vector<std::uint8_t> bytes;
  EXPECT_TRUE(cv::imencode(extension, image, bytes, params));
  return bytes;
}

void expectSize(const std::vector<std::uint8_t>& bytes, int width, int height) {
  const auto size = encodedImageSize(bytes);
  ASSERT_TRUE(size.has_value());
  EXPECT_EQ(size->width, static_cast<std::uint32_t>(width));
  EXPECT_EQ(size->height, static_cast<std::uint32_t>(height));
}

TEST(EncodedImageSize, ReadsWhatOpenCvsEncodersWrite) {
  expectSize(encoded(".png", cv::Mat(37, 53, CV_16UC1, cv::Scalar(1234))), 53, 37);
  expectSize(encoded(".png", cv::Mat(480, 640, CV_8UC3, cv::Scalar(1, 2, 3))), 640, 480);
  expectSize(encoded(".jpg", cv::Mat(31, 17, CV_8UC3, cv::Scalar(9, 8, 7))), 17, 31);
  expectSize(encoded(".jpg", cv::Mat(480, 640, CV_8UC3, cv::Scalar(9, 8, 7)), {cv::IMWRITE_JPEG_PROGRESSIVE, 1}), 640,
             480);
}

TEST(EncodedImageSize, CutOrForeignBytesHaveNoSize) {
  const std::vector<std::uint8_t> png = encoded(".png", cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 0, 0)));
  EXPECT_FALSE(encodedImageSize(std::vector<std::uint8_t>(png.begin(), png.begin() + 20)).has_value());
  const std::vector<std::uint8_t> jpeg = encoded(".jpg", cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 0, 0)));
  for (std::size_t cut = 0; cut < 8; ++cut) {
    EXPECT_FALSE(encodedImageSize(std::vector<std::uint8_t>(jpeg.begin(), jpeg.begin() + cut)).has_value()) << cut;
  }
  EXPECT_FALSE(encodedImageSize(encoded(".bmp", cv::Mat(4, 4, CV_8UC3, cv::Scalar(0, 0, 0)))).has_value());
  EXPECT_FALSE(encodedImageSize(std::vector<std::uint8_t>{}).has_value());
}

TEST(EncodedImageSize, AHugeDeclaredDepthImageIsRefusedBeforeDecoding) {
  TempDir tmp;
  writeBytes(tmp / "frame-000000.color.png", encoded(".png", cv::Mat(480, 640, CV_8UC3, cv::Scalar(0, 0, 0))));
  std::vector<std::uint8_t> depth = encoded(".png", cv::Mat(480, 640, CV_16UC1, cv::Scalar(1000)));
  // IHDR width and height (big-endian, bytes 16-23) rewritten to 30000 × 30000; decoding would need 1.8 GB.
  for (const std::size_t at : {16u, 20u}) {
    depth[at] = 0x00;
    depth[at + 1] = 0x00;
    depth[at + 2] = 0x75;
    depth[at + 3] = 0x30;
  }
  writeBytes(tmp / "frame-000000.depth.png", depth);
  SevenScenesReader reader(tmp.path());
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "frame-000000.depth.png: image is 30000x30000, expected 640x480");
}

}  // namespace
}  // namespace vifusion::datasets::test
