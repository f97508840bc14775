#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "vifusion/v4l2/ds_metadata.hpp"

namespace vifusion::v4l2 {
namespace {

constexpr int kWidth = 628;
constexpr int kHeight = 469;
constexpr std::uint32_t kBytesPerLine = kWidth * 2;

std::vector<std::uint8_t> depthFrame() { return std::vector<std::uint8_t>(std::size_t{kBytesPerLine} * kHeight, 0x5A); }

/// Puts a 32-bit little-endian word at dinghy word `index`, byte by byte (the documented layout, by hand).
void putWord(std::vector<std::uint8_t>& frame, int index, std::uint32_t value) {
  const std::size_t at = std::size_t{kBytesPerLine} * (kHeight - 1) + static_cast<std::size_t>(index) * 4;
  frame[at + 0] = static_cast<std::uint8_t>(value);
  frame[at + 1] = static_cast<std::uint8_t>(value >> 8);
  frame[at + 2] = static_cast<std::uint8_t>(value >> 16);
  frame[at + 3] = static_cast<std::uint8_t>(value >> 24);
}

std::vector<std::uint8_t> goodDepthFrame(std::uint32_t counter) {
  std::vector<std::uint8_t> frame = depthFrame();
  for (int i = 0; i < kDinghyWords; ++i) putWord(frame, i, 0);
  putWord(frame, 0, 0x04030201);  // magic (depth)
  putWord(frame, 1, counter);
  return frame;
}

TEST(Dinghy, ReadsTheDocumentedWordsFromTheLastRow) {
  std::vector<std::uint8_t> frame = goodDepthFrame(0x12345678);
  putWord(frame, 3, 111);  // exposure left sum
  putWord(frame, 5, 222);  // exposure left bright count
  putWord(frame, 8, 333);  // exposure right bright count
  putWord(frame, 9, 7);    // CAM-module status
  putWord(frame, 14, 0);   // VDF error status
  ProblemText problem;
  const auto dinghy = readDinghy(frame, kBytesPerLine, kHeight, problem);
  ASSERT_TRUE(dinghy.has_value()) << problem.view();
  EXPECT_EQ(dinghy->magic, 0x04030201u);
  EXPECT_EQ(dinghy->frame_counter, 0x12345678u);
  EXPECT_EQ(dinghy->exposure_left_sum, 111u);
  EXPECT_EQ(dinghy->exposure_left_bright_count, 222u);
  EXPECT_EQ(dinghy->exposure_right_bright_count, 333u);
  EXPECT_EQ(dinghy->cam_module_status, 7u);
  // Depth ignores the CAM-module status (librealsense checks it for IR only) …
  EXPECT_TRUE(checkDinghy(*dinghy, DinghyNode::kDepth, problem)) << problem.view();
  // … and the same row on the IR node fails on its magic first.
  EXPECT_FALSE(checkDinghy(*dinghy, DinghyNode::kInfrared, problem));
  EXPECT_EQ(problem.view(), "infrared dinghy magic 0x04030201, expected 0x08070605 (frame 305419896)");
}

TEST(Dinghy, RejectsBadMagicAndNonZeroStatusNamingTheField) {
  ProblemText problem;
  std::vector<std::uint8_t> frame = goodDepthFrame(42);
  putWord(frame, 0, 0xDEADBEEF);
  EXPECT_FALSE(checkDinghy(*readDinghy(frame, kBytesPerLine, kHeight, problem), DinghyNode::kDepth, problem));
  EXPECT_EQ(problem.view(), "depth dinghy magic 0xdeadbeef, expected 0x04030201 (frame 42)");

  frame = goodDepthFrame(43);
  putWord(frame, 2, 0x2);
  EXPECT_FALSE(checkDinghy(*readDinghy(frame, kBytesPerLine, kHeight, problem), DinghyNode::kDepth, problem));
  EXPECT_EQ(problem.view(), "depth dinghy frame status 0x00000002, expected 0 (frame 43)");

  frame = goodDepthFrame(44);
  putWord(frame, 14, 0x100);
  EXPECT_FALSE(checkDinghy(*readDinghy(frame, kBytesPerLine, kHeight, problem), DinghyNode::kDepth, problem));
  EXPECT_EQ(problem.view(), "depth dinghy VDF error status 0x00000100, expected 0 (frame 44)");

  frame = goodDepthFrame(45);
  putWord(frame, 0, 0x08070605);
  putWord(frame, 9, 0x1);
  EXPECT_FALSE(checkDinghy(*readDinghy(frame, kBytesPerLine, kHeight, problem), DinghyNode::kInfrared, problem));
  EXPECT_EQ(problem.view(), "infrared dinghy CAM-module status 0x00000001, expected 0 (frame 45)");
}

TEST(Dinghy, ShortFramesAreReportedNotRead) {
  ProblemText problem;
  const std::vector<std::uint8_t> frame(std::size_t{kBytesPerLine} * (kHeight - 1) + 63, 0);
  EXPECT_FALSE(readDinghy(frame, kBytesPerLine, kHeight, problem).has_value());
  EXPECT_NE(problem.view().find("cannot hold the 64-byte metadata row"), std::string_view::npos) << problem.view();
  EXPECT_FALSE(readDinghy(frame, kBytesPerLine, 0, problem).has_value());
  EXPECT_FALSE(readDinghy(frame, 32, 2, problem).has_value());  // a row narrower than the dinghy
  std::vector<std::uint8_t> too_small(10, 0);
  EXPECT_FALSE(writeDinghy(Dinghy{}, too_small, kBytesPerLine, kHeight));
}

TEST(Dinghy, WriteThenReadRoundTripsEveryField) {
  std::mt19937 random(17);
  std::vector<std::uint8_t> frame = depthFrame();
  for (int trial = 0; trial < 100; ++trial) {
    Dinghy written;
    written.magic = random();
    written.frame_counter = random();
    written.frame_status = random();
    written.exposure_left_sum = random();
    written.exposure_left_dark_count = random();
    written.exposure_left_bright_count = random();
    written.exposure_right_sum = random();
    written.exposure_right_dark_count = random();
    written.exposure_right_bright_count = random();
    written.cam_module_status = random();
    written.vdf_error_status = random();
    ASSERT_TRUE(writeDinghy(written, frame, kBytesPerLine, kHeight));
    ProblemText problem;
    const auto read = readDinghy(frame, kBytesPerLine, kHeight, problem);
    ASSERT_TRUE(read.has_value());
    EXPECT_EQ(read->magic, written.magic);
    EXPECT_EQ(read->frame_counter, written.frame_counter);
    EXPECT_EQ(read->frame_status, written.frame_status);
    EXPECT_EQ(read->exposure_left_sum, written.exposure_left_sum);
    EXPECT_EQ(read->exposure_left_dark_count, written.exposure_left_dark_count);
    EXPECT_EQ(read->exposure_left_bright_count, written.exposure_left_bright_count);
    EXPECT_EQ(read->exposure_right_sum, written.exposure_right_sum);
    EXPECT_EQ(read->exposure_right_dark_count, written.exposure_right_dark_count);
    EXPECT_EQ(read->exposure_right_bright_count, written.exposure_right_bright_count);
    EXPECT_EQ(read->cam_module_status, written.cam_module_status);
    EXPECT_EQ(read->vdf_error_status, written.vdf_error_status);
  }
  // The image rows above the dinghy are untouched.
  for (std::size_t i = 0; i < std::size_t{kBytesPerLine} * (kHeight - 1); ++i) ASSERT_EQ(frame[i], 0x5A) << i;
}

// ---- colour frame number ----

constexpr int kColourWidth = 640;
constexpr int kColourHeight = 480;
constexpr std::uint32_t kColourBytesPerLine = kColourWidth * 2;
constexpr std::size_t kCounterStart = std::size_t{kColourBytesPerLine} * kColourHeight - 64;  // last 32 pixels

TEST(ColourFrameNumber, BitsSitInTheLumaLsbOfTheLast32PixelsInPairSwappedOrder) {
  // Every luma LSB cleared, chroma bytes odd (LSB set) to prove only luma bytes are read.
  std::vector<std::uint8_t> frame(std::size_t{kColourBytesPerLine} * kColourHeight);
  for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = (i % 2 == 0) ? 0x80 : 0x81;
  ProblemText problem;
  EXPECT_EQ(readColourFrameNumber(frame, kColourBytesPerLine, kColourWidth, kColourHeight, problem), 0u);
  // Pixel 1 carries bit 31 and pixel 30 bit 0 (pixel i: bit 30 − i if even, 32 − i if odd).
  frame[kCounterStart + 1 * 2] |= 1;
  frame[kCounterStart + 30 * 2] |= 1;
  EXPECT_EQ(readColourFrameNumber(frame, kColourBytesPerLine, kColourWidth, kColourHeight, problem), 0x80000001u);
  // Pixel 0 → bit 30, pixel 31 → bit 1, pixel 2 → bit 28.
  frame[kCounterStart + 0 * 2] |= 1;
  frame[kCounterStart + 31 * 2] |= 1;
  frame[kCounterStart + 2 * 2] |= 1;
  EXPECT_EQ(readColourFrameNumber(frame, kColourBytesPerLine, kColourWidth, kColourHeight, problem), 0xD0000003u);
  // The pixel just before the 32 counter pixels does not count.
  frame[kCounterStart - 2] |= 1;
  EXPECT_EQ(readColourFrameNumber(frame, kColourBytesPerLine, kColourWidth, kColourHeight, problem), 0xD0000003u);
}

TEST(ColourFrameNumber, WriteThenReadRoundTripsAndTouchesOnlyThe32LumaLsbs) {
  std::mt19937 random(5);
  std::vector<std::uint8_t> frame(std::size_t{kColourBytesPerLine} * kColourHeight);
  for (auto& byte : frame) byte = static_cast<std::uint8_t>(random());
  const std::vector<std::uint8_t> before = frame;
  for (int trial = 0; trial < 200; ++trial) {
    const std::uint32_t number = random();
    ASSERT_TRUE(writeColourFrameNumber(number, frame, kColourBytesPerLine, kColourWidth, kColourHeight));
    ProblemText problem;
    EXPECT_EQ(readColourFrameNumber(frame, kColourBytesPerLine, kColourWidth, kColourHeight, problem), number);
  }
  int changed_elsewhere = 0;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const bool counter_luma = i >= kCounterStart && (i - kCounterStart) % 2 == 0;
    const std::uint8_t mask = counter_luma ? 0xFE : 0xFF;
    if ((frame[i] & mask) != (before[i] & mask)) ++changed_elsewhere;
  }
  EXPECT_EQ(changed_elsewhere, 0);
}

TEST(ColourFrameNumber, UsesTheStrideOfTheLastRowAndRefusesTinyFrames) {
  // 32×2 frame with 8 padding bytes per row: the counter pixels are the whole last row, before its padding.
  constexpr std::uint32_t kPaddedLine = 32 * 2 + 8;
  std::vector<std::uint8_t> frame(kPaddedLine * 2, 0);
  ASSERT_TRUE(writeColourFrameNumber(0xA5A5F00Fu, frame, kPaddedLine, 32, 2));
  for (std::size_t i = kPaddedLine * 2 - 8; i < frame.size(); ++i) EXPECT_EQ(frame[i], 0) << "padding byte " << i;
  ProblemText problem;
  EXPECT_EQ(readColourFrameNumber(frame, kPaddedLine, 32, 2, problem), 0xA5A5F00Fu);
  EXPECT_FALSE(readColourFrameNumber(frame, kPaddedLine, 31, 2, problem).has_value());  // fewer than 32 pixels
  EXPECT_NE(problem.view().find("cannot hold the 32 counter pixels"), std::string_view::npos) << problem.view();
  const std::vector<std::uint8_t> short_frame(kPaddedLine + 10, 0);
  EXPECT_FALSE(readColourFrameNumber(short_frame, kPaddedLine, 32, 2, problem).has_value());
}

TEST(ColourFrameNumber, CountsColourFramesWhenDepthRunsFaster) {
  EXPECT_EQ(colourFrameNumber(200, 60, 30), 100u);  // depth 60 Hz, colour 30 Hz: counts depth frames
  EXPECT_EQ(colourFrameNumber(201, 60, 30), 100u);
  EXPECT_EQ(colourFrameNumber(300, 90, 30), 100u);
  EXPECT_EQ(colourFrameNumber(200, 30, 30), 200u);
  EXPECT_EQ(colourFrameNumber(200, 0, 30), 200u);   // no depth stream
  EXPECT_EQ(colourFrameNumber(200, 30, 60), 200u);  // depth slower: unchanged
}

}  // namespace
}  // namespace vifusion::v4l2
