#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "vifusion/v4l2/yuyv.hpp"

namespace vifusion::v4l2 {
namespace {

// Real-valued BT.601 limited range written out independently of the implementation (the header's equations).
std::array<double, 3> referenceRgb(int y, int cb, int cr, double y_scale, double r_cr, double g_cb, double g_cr,
                                   double b_cb) {
  const double luma = y_scale * (y - 16);
  return {luma + r_cr * (cr - 128), luma - g_cb * (cb - 128) - g_cr * (cr - 128), luma + b_cb * (cb - 128)};
}

int level(double value) { return static_cast<int>(std::clamp(std::round(value), 0.0, 255.0)); }

TEST(Yuyv, HandComputedPixels) {
  // Values worked by hand from R = 1.164383(Y−16) + 1.596027(Cr−128), G = 1.164383(Y−16) − 0.391762(Cb−128)
  // − 0.812968(Cr−128), B = 1.164383(Y−16) + 2.017232(Cb−128).
  EXPECT_EQ(bt601LimitedToRgb(16, 128, 128), (Rgb8{0, 0, 0}));         // black
  EXPECT_EQ(bt601LimitedToRgb(235, 128, 128), (Rgb8{255, 255, 255}));  // white
  EXPECT_EQ(bt601LimitedToRgb(126, 128, 128), (Rgb8{128, 128, 128}));  // 110·255/219 = 128.08
  EXPECT_EQ(bt601LimitedToRgb(81, 90, 240), (Rgb8{254, 0, 0}));        // BT.601 red: 254.44, −0.48, −0.97
  EXPECT_EQ(bt601LimitedToRgb(145, 54, 34), (Rgb8{0, 255, 1}));        // green: 0.18, 255.61 (clamped), 0.93
  EXPECT_EQ(bt601LimitedToRgb(41, 240, 110), (Rgb8{0, 0, 255}));       // blue: 0.38, −0.13, 255.04
  EXPECT_EQ(bt601LimitedToRgb(200, 100, 150), (Rgb8{249, 207, 158}));  // 249.36, 207.33, 157.76
  EXPECT_EQ(bt601LimitedToRgb(60, 200, 70), (Rgb8{0, 70, 196}));       // −41.3 clamped, 70.18, 196.47
}

/// Largest difference, over the inputs visited, between one channel of the fixed-point conversion and the real
/// formula with the given coefficients; `differing` counts inputs that are not equal.
struct Agreement {
  int worst = 0;
  std::int64_t differing = 0;
};

void compare(int got, double real, Agreement& agreement) {
  const int difference = std::abs(got - level(real));
  agreement.worst = std::max(agreement.worst, difference);
  agreement.differing += difference != 0 ? 1 : 0;
}

TEST(Yuyv, WithinOneLevelOfTheRealFormulaAndOfOpenCvsCoefficients) {
  const double kr = 0.299;
  const double kb = 0.114;
  const double kg = 1.0 - kr - kb;
  const double c = 255.0 / 224.0;
  const double y_scale = 255.0 / 219.0;
  const double r_cr = c * 2 * (1 - kr);
  const double g_cb = c * 2 * (1 - kb) * kb / kg;
  const double g_cr = c * 2 * (1 - kr) * kr / kg;
  const double b_cb = c * 2 * (1 - kb);
  Agreement exact;
  Agreement opencv;
  // R depends on (Y, Cr) only and B on (Y, Cb) only: every input of theirs is visited.
  for (int y = 0; y < 256; ++y) {
    for (int chroma = 0; chroma < 256; ++chroma) {
      const auto u8 = [](int value) { return static_cast<std::uint8_t>(value); };
      const Rgb8 r_case = bt601LimitedToRgb(u8(y), 128, u8(chroma));
      const Rgb8 b_case = bt601LimitedToRgb(u8(y), u8(chroma), 128);
      compare(r_case.r, referenceRgb(y, 128, chroma, y_scale, r_cr, g_cb, g_cr, b_cb)[0], exact);
      compare(b_case.b, referenceRgb(y, chroma, 128, y_scale, r_cr, g_cb, g_cr, b_cb)[2], exact);
      compare(r_case.r, referenceRgb(y, 128, chroma, 1.164, 1.596, 0.391, 0.813, 2.018)[0], opencv);
      compare(b_case.b, referenceRgb(y, chroma, 128, 1.164, 1.596, 0.391, 0.813, 2.018)[2], opencv);
    }
  }
  // G depends on all three: every Y and Cb, every 4th Cr (4.2 million inputs; all 2²⁴ take ~17 s under qemu).
  constexpr int kCrStep = 4;
  for (int y = 0; y < 256; ++y) {
    for (int cb = 0; cb < 256; ++cb) {
      for (int cr = 1; cr < 256; cr += kCrStep) {
        const Rgb8 got = bt601LimitedToRgb(static_cast<std::uint8_t>(y), static_cast<std::uint8_t>(cb),
                                           static_cast<std::uint8_t>(cr));
        compare(got.g, referenceRgb(y, cb, cr, y_scale, r_cr, g_cb, g_cr, b_cb)[1], exact);
        compare(got.g, referenceRgb(y, cb, cr, 1.164, 1.596, 0.391, 0.813, 2.018)[1], opencv);
      }
    }
  }
  EXPECT_LE(exact.worst, 1);
  EXPECT_LE(opencv.worst, 1);
  // Fixed point differs only where the real value lies within ~10⁻⁴ of a rounding boundary: 168 channel values
  // of the 4.3 million visited.
  EXPECT_LE(exact.differing, 168) << "of " << 2 * 65536 + 65536 * 64 << " channel values";
  RecordProperty("differing_from_exact", static_cast<int>(exact.differing));
  RecordProperty("differing_from_opencv", static_cast<int>(opencv.differing));
}

TEST(Yuyv, FrameUsesStrideAndSharesChromaInPairs) {
  // 4×2 image, rows 12 bytes apart (8 bytes of pixels + 4 bytes of padding that must be ignored).
  constexpr std::uint32_t kBytesPerLine = 12;
  const std::vector<std::uint8_t> frame = {
      // row 0: pair (Y0 126, Y1 235, Cb 128, Cr 128), pair (Y 81, 16, Cb 90, Cr 240)
      126, 128, 235, 128, 81, 90, 16, 240, 0xEE, 0xEE, 0xEE, 0xEE,
      // row 1: pair (200, 60 with Cb 100 Cr 150), pair (145, 145 with Cb 54, Cr 34)
      200, 100, 60, 150, 145, 54, 145, 34, 0xEE, 0xEE, 0xEE, 0xEE};
  Image<Rgb8> rgb(4, 2);
  ProblemText problem;
  ASSERT_TRUE(yuyvToRgb(frame, kBytesPerLine, rgb.view(), problem)) << problem.view();
  EXPECT_EQ(rgb(0, 0), (Rgb8{128, 128, 128}));
  EXPECT_EQ(rgb(1, 0), (Rgb8{255, 255, 255}));
  EXPECT_EQ(rgb(2, 0), (Rgb8{254, 0, 0}));
  EXPECT_EQ(rgb(3, 0), bt601LimitedToRgb(16, 90, 240));
  EXPECT_EQ(rgb(0, 1), (Rgb8{249, 207, 158}));
  EXPECT_EQ(rgb(1, 1), bt601LimitedToRgb(60, 100, 150));
  EXPECT_EQ(rgb(2, 1), (Rgb8{0, 255, 1}));
  EXPECT_EQ(rgb(3, 1), (Rgb8{0, 255, 1}));
}

TEST(Yuyv, RefusesOddWidthsAndShortFrames) {
  ProblemText problem;
  Image<Rgb8> odd(3, 2);
  std::vector<std::uint8_t> frame(64, 128);
  EXPECT_FALSE(yuyvToRgb(frame, 8, odd.view(), problem));
  EXPECT_NE(problem.view().find("width 3 must be even"), std::string_view::npos) << problem.view();

  Image<Rgb8> rgb(4, 2);
  const std::vector<std::uint8_t> short_frame(15, 128);  // 8 + 8 bytes needed
  EXPECT_FALSE(yuyvToRgb(short_frame, 8, rgb.view(), problem));
  EXPECT_NE(problem.view().find("frame of 15 bytes"), std::string_view::npos) << problem.view();
  EXPECT_NE(problem.view().find("needs 16"), std::string_view::npos) << problem.view();
  EXPECT_FALSE(yuyvToRgb(frame, 6, rgb.view(), problem));  // a row of 4 pixels needs 8 bytes per line
}

}  // namespace
}  // namespace vifusion::v4l2
