#pragma once
// Kinect-like sensor noise for rendered frames, after ICL-NUIM (Handa et al., ICRA 2014) and its
// reference implementation ankurhanda/simkinect add_noise.py (algorithms.md §6). Depth, from clean
// metric depth:
//   1. lateral jitter: each pixel reads the clean depth at its position plus N(0, σ²·I₂) [px], bilinear,
//      clamped to the image (nearest neighbour where a bilinear tap has no depth, so holes do not
//      bleed into fake near values);
//   2. disparity d = f·b / z [px], f = 480 px, b = 0.075 m, rounded to 1/8 px;
//   3. dot-pattern filtering, a procedural stand-in for simkinect's filterDisp with its shipped Kinect
//      dot image: the projector pattern is one dot per 3×3 pixel cell at a hashed position inside the
//      cell (fixed, like a real projector, so it does not depend on the seed). A dot is accepted when,
//      in the 9×9 window around it, more than 1/1.2 of the window's dots have depth and more than
//      1/1.2 are inliers, |d − mean d|/(1.44·r²) < 0.1 px (r = distance to the dot [px], weight 1 at the
//      dot; mean over all valid window pixels). Every pixel then takes the disparity of the nearest
//      accepted dot within r² ≤ 9 (ties: first dot in raster order, as simkinect's sequential fill),
//      or none. Only dots whose window lies inside the image count, so a ragged border of up to 6 px
//      has no depth. Every pixel lies within r² ≤ 8 of its own cell's dot, so flat surfaces come out
//      complete; holes appear in blobs along depth edges (a few per cent of edge pixels: a dot is
//      rejected only when two of its ~9 window dots within ~2 px are outliers), on thin structures and
//      next to missing depth. Shadowing by the projector baseline is not modelled (nor is it in
//      simkinect);
//   4. z = f·b / d, z_cm = round(100·z), z_noisy_cm = 35130 / round(35130 / z_cm + N(0, 1)·σ + 0.5),
//      σ = 1/6 (simkinect's constants; the +0.5 is theirs too), stored at depth_scale units per metre.
//      The +0.5 biases the index by +0.5 on average, so the noisy depth is short by the inverse-depth
//      bias kSimulatedInverseDepthBias_per_m (0.28 % at 2 m, 0.57 % at 4 m). The simulator does not write
//      it into calibration.yaml: like a real sensor's disparity offset it is there to be measured
//      (`vifusion calib noise`), and the sim's JSON summary gives the true value to compare with.
// Colour: independent N(0, σ²) per channel on the 0–255 scale, rounded and clamped (σ = 4 synthetic,
// 1 real, paper Table I). Rounding to 8 bits adds 1/12 to the variance: a measured σ is √(σ² + 1/12).
//
// All randomness is counter-based (counter_rng.hpp) on (seed, frame_index, pixel), so results are
// identical for any thread count. Rounding is to nearest with ties to even, like numpy's round.

#include <Eigen/Core>
#include <cstdint>

#include "vifusion/core/camera_noise_model.hpp"
#include "vifusion/core/image.hpp"
#include "vifusion/scene/row_pool.hpp"

namespace vifusion::scene {

/// simkinect's depth-banding constant: the noisy depth is 35130 / (integer index) [cm].
inline constexpr double kKinectBandingConstant_cm = 35130.0;

/// Mean inverse-depth error of step 4 [1/m]: 1/z_noisy = 1/z + 0.5 / 35130 cm⁻¹ on average.
inline constexpr double kSimulatedInverseDepthBias_per_m = 0.5 * 100.0 / kKinectBandingConstant_cm;

struct SensorNoiseOptions {
  std::uint64_t seed = 0;
  double jitter_sigma_px = 0.5;          ///< step 1; 0 switches it off
  double focal_length_px = 480.0;        ///< step 2: f of the disparity model (not the camera's) [px]
  double baseline_m = 0.075;             ///< step 2: projector–camera baseline [m]
  double disparity_step_px = 1.0 / 8.0;  ///< step 2: disparity resolution [px]; 0 switches rounding off
  bool dot_pattern = true;               ///< step 3
  double depth_noise_sigma = 1.0 / 6.0;  ///< step 4: σ of the noise on 35130/z_cm (the banding stays at 0)
  double depth_scale = 5000.0;           ///< output depth units per metre
  double intensity_sigma = 4.0;          ///< colour noise σ on the 0–255 scale; 0 switches it off
};

/// The noise these options configure, in the terms `vifusion calib noise` measures (core/camera_noise_model.hpp):
///   σ_d² = step²/12 + (f·b / 351.3 m)²·(σ² + 1/12): step 2's disparity rounding, and step 4's index noise and
///          rounding (index = 351.3 m / z, so one index unit is f·b / 351.3 m of disparity);
///   q = 1 cm (step 4 rounds z to centimetres); lateral σ_px = step 1's jitter / subsampling, in the pixels of
///   an image subsampled by that factor from the one the noise was applied to (sensor_resolution.hpp);
///   grey σ² = (w_r² + w_g² + w_b²)·(intensity σ² + 1/12) for grey = w·(R, G, B) (8-bit rounding of each
///   channel); the weights are the caller's (preprocessing's grey conversion).
/// Correlation is left at none: the dot pattern's sharing of one disparity over a 3×3 cell has no closed form
/// worth trusting over the measurement.
CameraNoiseModel configuredNoiseModel(const SensorNoiseOptions& options, const Eigen::Vector3d& grey_weights,
                                      int subsampling);

class SensorNoise {
 public:
  /// Keeps a reference to pool, which must outlive this object. Throws std::invalid_argument for a
  /// non-positive focal length, baseline or depth scale, or a negative σ or step.
  SensorNoise(const SensorNoiseOptions& options, RowPool& pool);

  /// Sizes the scratch images (disparity, dot pattern, accepted dots) for width × height; the only
  /// allocation this class makes. addDepthNoise() calls it, so only the first frame (or a size
  /// change) allocates.
  void reserve(int width, int height);

  /// Steps 1–4 from clean depth [m, 0 = none] into noisy_depth [depth_scale units per metre,
  /// 0 = none]; both views the same size (std::invalid_argument otherwise).
  void addDepthNoise(ImageView<const float> depth_m, ImageView<std::uint16_t> noisy_depth, std::uint64_t frame_index);

  /// The same noisy image subsampled by s ≥ 1 (sensor_resolution.hpp): noisy_depth(x, y) is the value the
  /// call above gives at depth_m's pixel (s·x, s·y), equal to it bit for bit; depth_m is s × noisy_depth's
  /// size (std::invalid_argument otherwise). Step 4 runs only at the kept pixels.
  void addDepthNoise(ImageView<const float> depth_m, ImageView<std::uint16_t> noisy_depth, std::uint64_t frame_index,
                     int subsampling);

  /// Gaussian colour noise in place.
  void addIntensityNoise(ImageView<Rgb8> rgb, std::uint64_t frame_index) const;

  const SensorNoiseOptions& options() const { return options_; }

 private:
  void jitterAndQuantise(ImageView<const float> depth_m, std::uint64_t frame_index);
  void acceptDots();
  void fillAndAddNoise(ImageView<std::uint16_t> noisy_depth, int subsampling, std::uint64_t frame_index) const;

  SensorNoiseOptions options_;
  RowPool& pool_;
  Image<float> disparity_px_;     ///< after steps 1–2; 0 = no depth
  Image<std::uint8_t> dots_;      ///< projector pattern: 1 at a dot
  Image<std::uint8_t> accepted_;  ///< step 3: 1 where a dot passed the window test
};

}  // namespace vifusion::scene
