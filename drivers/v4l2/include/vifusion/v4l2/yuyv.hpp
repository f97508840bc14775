#pragma once
// YUYV (YUY2) 4:2:2 → RGB888 with ITU-R BT.601 in limited ("studio") range, the colour maths UVC webcams
// (the ZR300 colour camera among them) are decoded with:
//
//   R = 255/219·(Y − 16)                      + 255/224·1.402·(Cr − 128)
//   G = 255/219·(Y − 16) − 255/224·(1.772·0.114/0.587)·(Cb − 128) − 255/224·(1.402·0.299/0.587)·(Cr − 128)
//   B = 255/219·(Y − 16) + 255/224·1.772·(Cb − 128)
//
// rounded to nearest and clamped to [0, 255]. Integer arithmetic: coefficients with 20 fractional bits, which
// agree with the real-valued formula to within one level (R and B checked for every input, G for a quarter
// of all inputs). OpenCV's COLOR_YUV2RGB_YUYV uses the same equations with 3-decimal coefficients (1.164,
// 1.596, 0.391, 0.813, 2.018), also within one level of these. Memory order per pixel pair: Y0 Cb Y1 Cr;
// both pixels share Cb and Cr.

#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/v4l2/problem_text.hpp"

namespace vifusion::v4l2 {

/// One BT.601 limited-range Y, Cb, Cr triple to RGB888.
Rgb8 bt601LimitedToRgb(std::uint8_t y, std::uint8_t cb, std::uint8_t cr);

/// Converts a YUYV frame (rows `bytes_per_line` apart) into the caller's image, whose width (even) and
/// height say how much of the frame to convert. No allocation. Returns false and sets `problem` (naming the
/// size that is wrong) when the frame is too short for the image or the width is odd.
bool yuyvToRgb(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line, ImageView<Rgb8> rgb,
               ProblemText& problem);

}  // namespace vifusion::v4l2
