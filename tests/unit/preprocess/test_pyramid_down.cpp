#include <gtest/gtest.h>

#include <stdexcept>
#include <utility>

#include "synthetic_images.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

using test::fillImage;

TEST(PyramidDownDepth, DefaultGateIsThreeSigmaRange) {
  EXPECT_FLOAT_EQ(PyramidDownDepthParams{}.range_gate_m, 3.0f * 0.03f);
}

TEST(PyramidDownDepth, ConstantStaysConstantForEvenAndOddSizes) {
  for (const auto& [w, h] : {std::pair{8, 6}, std::pair{9, 7}}) {
    Image<float> fine(w, h, 1.25f);
    Image<float> coarse(w / 2, h / 2, -1.0f);
    pyramidDownDepthCpu(fine.view(), {.src_width = w, .src_height = h}, coarse.view());
    for (int y = 0; y < h / 2; ++y) {
      for (int x = 0; x < w / 2; ++x) EXPECT_EQ(coarse(x, y), 1.25f) << w << "x" << h << " at " << x << "," << y;
    }
  }
}

TEST(PyramidDownDepth, LinearRampSamplesTheCentreInTheInterior) {
  // The symmetric kernel reproduces a linear function at its centre when no tap is dropped.
  Image<float> fine(16, 12);
  fillImage(fine, [](int x, int y) { return 1.0f + 0.01f * static_cast<float>(x) + 0.005f * static_cast<float>(y); });
  Image<float> coarse(8, 6);
  pyramidDownDepthCpu(fine.view(), {.src_width = 16, .src_height = 12}, coarse.view());
  for (int y = 1; 2 * y + 2 < 12; ++y) {
    for (int x = 1; 2 * x + 2 < 16; ++x) EXPECT_NEAR(coarse(x, y), fine(2 * x, 2 * y), 1e-6f) << x << "," << y;
  }
}

TEST(PyramidDownDepth, StepEdgeIsNotAveraged) {
  Image<float> fine(20, 8);
  fillImage(fine, [](int x, int) { return x < 9 ? 1.0f : 1.5f; });
  Image<float> coarse(10, 4);
  pyramidDownDepthCpu(fine.view(), {.src_width = 20, .src_height = 8}, coarse.view());
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 10; ++x) EXPECT_EQ(coarse(x, y), fine(2 * x, 2 * y)) << x << "," << y;
  }
}

TEST(PyramidDownDepth, InvalidCentreGivesInvalidAndInvalidNeighboursAreSkipped) {
  // Zeros on every odd column: centres (even columns) stay valid and see only value 3.
  Image<float> fine(12, 10);
  fillImage(fine, [](int x, int y) { return (x % 2 == 1) ? 0.0f : ((x == 4 && y == 4) ? 0.0f : 3.0f); });
  Image<float> coarse(6, 5, -1.0f);
  pyramidDownDepthCpu(fine.view(), {.src_width = 12, .src_height = 10}, coarse.view());
  for (int y = 0; y < 5; ++y) {
    for (int x = 0; x < 6; ++x) {
      if (x == 2 && y == 2) {
        EXPECT_EQ(coarse(x, y), 0.0f);
      } else {
        EXPECT_EQ(coarse(x, y), 3.0f) << x << "," << y;
      }
    }
  }
}

TEST(PyramidDownDepth, KnownAnswerWithGatedNeighbours) {
  Image<float> fine(6, 6, 0.0f);
  fine(2, 2) = 1.0f;   // centre of coarse (1, 1)
  fine(3, 2) = 1.05f;  // within 0.09 m: used with weight 0.375·0.25
  fine(2, 3) = 1.1f;   // 0.1 m away: dropped
  fine(0, 0) = 1.0f;   // corner tap, weight 0.0625²
  Image<float> coarse(3, 3);
  pyramidDownDepthCpu(fine.view(), {.src_width = 6, .src_height = 6}, coarse.view());
  const double w_centre = 0.375 * 0.375;
  const double w_side = 0.375 * 0.25;
  const double w_corner = 0.0625 * 0.0625;
  const double expected = (w_centre * 1.0 + w_side * static_cast<double>(1.05f) + w_corner * 1.0) /
                          (w_centre + w_side + w_corner);
  EXPECT_NEAR(coarse(1, 1), expected, 1e-7);
}

TEST(PyramidDownDepth, GateIsInclusive) {
  Image<float> fine(4, 4, 0.0f);
  fine(0, 0) = 1.0f;
  fine(1, 0) = 1.25f;  // exactly at the gate: used
  fine(0, 1) = 1.5f;   // beyond: dropped
  Image<float> coarse(2, 2);
  pyramidDownDepthCpu(fine.view(), {.src_width = 4, .src_height = 4, .range_gate_m = 0.25f}, coarse.view());
  const double w_centre = 0.375 * 0.375;
  const double w_side = 0.375 * 0.25;
  EXPECT_NEAR(coarse(0, 0), (w_centre * 1.0 + w_side * 1.25) / (w_centre + w_side), 1e-7);
}

TEST(PyramidDownDepth, RejectsWrongOutputSize) {
  Image<float> fine(8, 8, 1.0f);
  Image<float> coarse(4, 3);
  EXPECT_THROW(pyramidDownDepthCpu(fine.view(), {.src_width = 8, .src_height = 8}, coarse.view()),
               std::invalid_argument);
}

TEST(PyramidDownIntensity, ConstantStaysConstantIncludingBorders) {
  Image<float> fine(11, 9, 117.0f);
  Image<float> coarse(5, 4);
  pyramidDownIntensityCpu(fine.view(), {.src_width = 11, .src_height = 9}, coarse.view());
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) EXPECT_EQ(coarse(x, y), 117.0f);
  }
}

TEST(PyramidDownIntensity, LinearRampSamplesTheCentreInTheInterior) {
  Image<float> fine(16, 14);
  fillImage(fine, [](int x, int y) { return 3.0f * static_cast<float>(x) + 2.0f * static_cast<float>(y) + 5.0f; });
  Image<float> coarse(8, 7);
  pyramidDownIntensityCpu(fine.view(), {.src_width = 16, .src_height = 14}, coarse.view());
  for (int y = 1; 2 * y + 2 < 14; ++y) {
    for (int x = 1; 2 * x + 2 < 16; ++x) EXPECT_EQ(coarse(x, y), fine(2 * x, 2 * y)) << x << "," << y;
  }
}

TEST(PyramidDownIntensity, BordersReplicateEdgePixels) {
  // I = x. At coarse x = 0 the taps read columns {0, 0, 0, 1, 2}; at the last coarse column
  // (centre 6 of 8) they read {4, 5, 6, 7, 7}.
  Image<float> fine(8, 4);
  fillImage(fine, [](int x, int) { return static_cast<float>(x); });
  Image<float> coarse(4, 2);
  pyramidDownIntensityCpu(fine.view(), {.src_width = 8, .src_height = 4}, coarse.view());
  for (int y = 0; y < 2; ++y) {
    EXPECT_EQ(coarse(0, y), 0.25f * 1.0f + 0.0625f * 2.0f);
    EXPECT_EQ(coarse(3, y), 0.0625f * 4.0f + 0.25f * 5.0f + 0.375f * 6.0f + 0.25f * 7.0f + 0.0625f * 7.0f);
  }
}

TEST(PyramidDownIntensity, RejectsWrongOutputSize) {
  Image<float> fine(7, 5);
  Image<float> coarse(4, 2);  // floor(7/2) = 3
  EXPECT_THROW(pyramidDownIntensityCpu(fine.view(), {.src_width = 7, .src_height = 5}, coarse.view()),
               std::invalid_argument);
}

}  // namespace
}  // namespace vifusion::preprocess
