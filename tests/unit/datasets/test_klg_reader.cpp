#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <opencv2/imgcodecs.hpp>

#include "fixtures.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/klg_reader.hpp"
#include "vifusion/test/klg_log.hpp"

namespace vifusion::datasets::test {
namespace {

using vifusion::test::klgBytes;
using vifusion::test::KlgFrame;

std::vector<std::uint8_t> rawDepth(int k) {
  const cv::Mat depth = depthImage(640, 480, k);
  return {depth.data, depth.data + depth.total() * depth.elemSize()};
}

std::vector<std::uint8_t> rawRgb(int k) {
  std::vector<std::uint8_t> bytes;
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) {
      const cv::Vec3b rgb = rgbPattern(x, y, k);
      bytes.insert(bytes.end(), {rgb[0], rgb[1], rgb[2]});
    }
  }
  return bytes;
}

std::vector<std::uint8_t> zlibCompress(const std::vector<std::uint8_t>& raw) {
  uLongf size = compressBound(static_cast<uLong>(raw.size()));
  std::vector<std::uint8_t> out(size);
  EXPECT_EQ(compress2(out.data(), &size, raw.data(), static_cast<uLong>(raw.size()), Z_BEST_SPEED), Z_OK);
  out.resize(size);
  return out;
}

class KlgReaderTest : public ::testing::Test {
 protected:
  std::filesystem::path write(const std::vector<KlgFrame>& frames, std::int32_t frame_count = -1) {
    writeBytes(path_, klgBytes(frames, frame_count < 0 ? static_cast<std::int32_t>(frames.size()) : frame_count));
    return path_;
  }
  TempDir tmp_;
  std::filesystem::path path_ = tmp_ / "log.klg";
};

TEST_F(KlgReaderTest, DecodesRawFramesExactly) {
  write({{1'000'000, rawDepth(0), rawRgb(0)}, {1'033'333, rawDepth(1), rawRgb(1)}});
  KlgReader reader(path_);
  EXPECT_EQ(reader.frameCount(), 2u);
  EXPECT_EQ(reader.calibration().camera.fx, 528.0);
  EXPECT_EQ(reader.calibration().depth_scale_m, 0.001);
  RgbdFrame frame;
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 1'000'000'000);
  EXPECT_TRUE(holdsPattern(frame, 0));
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.t_ns, 1'033'333'000);
  EXPECT_EQ(frame.index, 1);
  EXPECT_TRUE(holdsPattern(frame, 1));
  EXPECT_FALSE(reader.nextFrame(frame));
  // Rewound (a looped replay's seam), it delivers the log again from its first frame.
  ASSERT_TRUE(reader.rewind());
  ASSERT_TRUE(reader.nextFrame(frame));
  EXPECT_EQ(frame.index, 0);
  EXPECT_EQ(frame.t_ns, 1'000'000'000);
  EXPECT_TRUE(holdsPattern(frame, 0));
}

TEST_F(KlgReaderTest, ZlibDepthRoundTripsAndJpegAndEmptyColourDecode) {
  // Logger2 passes R,G,B bytes to OpenCV as if B,G,R; decoding returns R,G,B in memory order.
  const cv::Mat rgb_as_bgr(480, 640, CV_8UC3, cv::Scalar(200, 50, 10));
  std::vector<std::uint8_t> jpeg;
  ASSERT_TRUE(cv::imencode(".jpg", rgb_as_bgr, jpeg, {cv::IMWRITE_JPEG_QUALITY, 95}));
  write({{10, zlibCompress(rawDepth(3)), jpeg}, {20, zlibCompress(rawDepth(4)), {}}});

  const std::unique_ptr<DatasetReader> reader = openDataset("klg:" + path_.string());
  RgbdFrame frame;
  ASSERT_TRUE(reader->nextFrame(frame));
  for (int y = 0; y < 480; ++y) {
    for (int x = 0; x < 640; ++x) ASSERT_EQ(frame.depth(x, y), depthPattern(x, y, 3));
  }
  EXPECT_NEAR(frame.rgb(100, 100).r, 200, 3);
  EXPECT_NEAR(frame.rgb(100, 100).g, 50, 3);
  EXPECT_NEAR(frame.rgb(100, 100).b, 10, 3);
  ASSERT_TRUE(reader->nextFrame(frame));
  EXPECT_EQ(frame.depth(639, 479), depthPattern(639, 479, 4));
  EXPECT_EQ(frame.rgb(100, 100), Rgb8{});  // image size 0: no colour
}

TEST_F(KlgReaderTest, TruncatedLogIsAnErrorNamingTheFrame) {
  write({{10, rawDepth(0), rawRgb(0)}, {20, rawDepth(1), rawRgb(1)}});
  std::filesystem::resize_file(path_, std::filesystem::file_size(path_) - 1000);
  expectError([&] { KlgReader reader(path_); },
              "log.klg frame 1: depth (614400 bytes) and image (921600 bytes) run past the end of the file");
}

TEST_F(KlgReaderTest, FrameCountBeyondTheDataIsAnError) {
  write({{10, rawDepth(0), {}}}, 3);
  expectError([&] { KlgReader reader(path_); }, "log.klg frame 1: header runs past the end of the file");
}

TEST_F(KlgReaderTest, BytesAfterTheLastFrameAreAnError) {
  write({{10, rawDepth(0), {}}, {20, rawDepth(0), {}}}, 1);
  expectError([&] { KlgReader reader(path_); }, "log.klg: 614416 bytes after the last of 1 frames");
}

TEST_F(KlgReaderTest, NegativeOrHugeSizesAreErrors) {
  std::vector<std::uint8_t> bytes;
  vifusion::test::appendLittleEndian(bytes, std::int32_t{1});
  vifusion::test::appendLittleEndian(bytes, std::int64_t{10});
  vifusion::test::appendLittleEndian(bytes, std::int32_t{-5});
  vifusion::test::appendLittleEndian(bytes, std::int32_t{0});
  writeBytes(path_, bytes);
  expectError([&] { KlgReader reader(path_); }, "log.klg frame 0: depth size -5 must be > 0");

  bytes.resize(4 + 8);
  vifusion::test::appendLittleEndian(bytes, std::int32_t{100});
  vifusion::test::appendLittleEndian(bytes, std::int32_t{2'000'000'000});
  bytes.resize(bytes.size() + 100);
  writeBytes(path_, bytes);
  expectError([&] { KlgReader reader(path_); },
              "log.klg frame 0: depth (100 bytes) and image (2000000000 bytes) run past");

  writeBytes(path_, {1, 2});
  expectError([&] { KlgReader reader(path_); }, "log.klg: truncated: 2 bytes, no frame count");
  write({}, 0);
  expectError([&] { KlgReader reader(path_); }, "log.klg: frame count is 0, expected > 0");
}

TEST_F(KlgReaderTest, TimeGoingBackwardsIsAnError) {
  write({{1'033'000, rawDepth(0), {}}, {1'000'000, rawDepth(1), {}}});
  expectError([&] { KlgReader reader(path_); }, "log.klg frame 1: timestamp goes backwards by 33 ms");
}

TEST_F(KlgReaderTest, CorruptZlibDepthIsAnError) {
  std::vector<std::uint8_t> corrupt = zlibCompress(rawDepth(0));
  for (std::size_t k = 2; k < corrupt.size(); k += 3) corrupt[k] ^= 0x5a;
  write({{10, corrupt, {}}});
  KlgReader reader(path_);
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "log.klg frame 0: zlib depth (");
}

TEST_F(KlgReaderTest, ZlibDepthOfTheWrongSizeIsAnError) {
  write({{10, zlibCompress(std::vector<std::uint8_t>(1000, 7)), {}}});
  KlgReader reader(path_);
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "decompresses to 1000 bytes, expected 614400");
}

TEST_F(KlgReaderTest, CorruptJpegIsAnError) {
  write({{10, rawDepth(0), std::vector<std::uint8_t>(5000, 0x42)}});
  KlgReader reader(path_);
  RgbdFrame frame;
  expectError([&] { reader.nextFrame(frame); }, "log.klg frame 0 JPEG colour: truncated or corrupt compressed image");
}

TEST_F(KlgReaderTest, MissingFileIsAnError) {
  expectError([&] { KlgReader reader(tmp_ / "none.klg"); }, "none.klg: cannot open file");
}

}  // namespace
}  // namespace vifusion::datasets::test
