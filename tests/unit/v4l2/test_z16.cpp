#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "vifusion/v4l2/z16.hpp"

namespace vifusion::v4l2 {
namespace {

TEST(Z16, LittleEndianRowsWithStrideIntoACentredView) {
  // 3×2 depth frame, rows 8 bytes apart (6 bytes of pixels + 2 padding bytes that must not be copied).
  const std::vector<std::uint8_t> frame = {0x01, 0x00, 0x34, 0x12, 0xFF, 0xFF, 0xAA, 0xAA,
                                           0x00, 0x01, 0xE8, 0x03, 0x00, 0x00, 0xAA, 0xAA};
  // Padded like librealsense: a 7×6 image, the frame placed at (2, 2); the border stays zero.
  Image<std::uint16_t> depth(7, 6, 0);
  ImageView<std::uint16_t> centre(depth.data() + 2 * 7 + 2, 3, 2, 7);
  ProblemText problem;
  ASSERT_TRUE(z16ToDepth(frame, 8, centre, problem)) << problem.view();
  EXPECT_EQ(depth(2, 2), 1);
  EXPECT_EQ(depth(3, 2), 0x1234);
  EXPECT_EQ(depth(4, 2), 0xFFFF);
  EXPECT_EQ(depth(2, 3), 256);
  EXPECT_EQ(depth(3, 3), 1000);
  EXPECT_EQ(depth(4, 3), 0);
  int non_zero_outside = 0;
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 7; ++x) {
      const bool inside = x >= 2 && x < 5 && y >= 2 && y < 4;
      if (!inside && depth(x, y) != 0) ++non_zero_outside;
    }
  }
  EXPECT_EQ(non_zero_outside, 0);
}

TEST(Z16, RefusesShortFrames) {
  Image<std::uint16_t> depth(3, 2);
  const std::vector<std::uint8_t> frame(13, 0);  // 8 + 6 bytes needed
  ProblemText problem;
  EXPECT_FALSE(z16ToDepth(frame, 8, depth.view(), problem));
  EXPECT_NE(problem.view().find("frame of 13 bytes"), std::string_view::npos) << problem.view();
  EXPECT_NE(problem.view().find("needs 14"), std::string_view::npos) << problem.view();
  EXPECT_FALSE(z16ToDepth(std::vector<std::uint8_t>(64, 0), 4, depth.view(), problem));  // 3 px need 6 bytes/line
}

TEST(Z16, DepthScaleFromDepthUnits) {
  EXPECT_DOUBLE_EQ(depthScaleMetres(1000), 0.001);  // firmware default: 1 unit = 1 mm
  EXPECT_DOUBLE_EQ(depthScaleMetres(100), 0.0001);
  EXPECT_DOUBLE_EQ(depthScaleMetres(0), 0.0);
}

}  // namespace
}  // namespace vifusion::v4l2
