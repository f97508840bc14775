#pragma once
// The small image that ferns are evaluated on and that a keyframe keeps for verification: the input frame
// averaged over factor × factor blocks. Block means (not subsampling) so that sensor noise and a pixel or two
// of view change move the values little; depth is averaged over the block's valid pixels only, so holes do
// not drag the mean towards zero.

#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::loop {

/// Block-averaged colour and metric depth, sized once. Pixel (u, v) covers input pixels
/// [u·f, u·f + f) × [v·f, v·f + f) for downsampling factor f, in the input camera's frame. Its centre is input
/// pixel u·f + (f − 1)/2, so registering against it uses the input's intrinsics scaled: fx/f, fy/f,
/// (cx − (f − 1)/2)/f, (cy − (f − 1)/2)/f (pixel centres at integer coordinates).
struct FernImage {
  FernImage() = default;
  /// Allocates width × height pixels (the only allocation).
  FernImage(int width, int height) : rgb(width, height), depth_m(width, height) {}

  int width() const { return rgb.width(); }
  int height() const { return rgb.height(); }

  Image<Rgb8> rgb;       ///< block mean of R, G, B over all the block's pixels, rounded to nearest
  Image<float> depth_m;  ///< block mean depth over the block's valid pixels [m]; 0 = invalid block
};

/// Averages a registered frame into `out` (out must be width/factor × height/factor). A depth pixel is valid
/// when raw ≠ 0 and raw·depth_scale_m ≤ max_depth_m; a block with fewer than half (2·valid < factor²) valid
/// pixels is invalid. Sums are exact integers, so the result does not depend on the summation order.
/// Allocates nothing.
/// @param[in] rgb, depth_raw  registered colour and raw depth of the same size, multiples of factor
/// @param[in] depth_scale_m   metres per raw depth unit, > 0
/// @param[in] max_depth_m     depth beyond this is missing [m]
/// @throws vifusion::Error when sizes disagree or are not multiples of factor (a configuration mistake)
void downsampleForFerns(ImageView<const Rgb8> rgb, ImageView<const std::uint16_t> depth_raw, double depth_scale_m,
                        int factor, float max_depth_m, FernImage& out);

/// The same for a frame (its rgb and depth images and depth_scale_m).
void downsampleForFerns(const RgbdFrame& frame, int factor, float max_depth_m, FernImage& out);

}  // namespace vifusion::loop
