#pragma once
// The measured noise of an RGB-D camera's depth and intensity (issue 21): what `vifusion calib noise`
// estimates and calibration.yaml's `depth_noise:` and `intensity_noise:` mappings hold.
//
// Depth. Stereo and structured-light sensors measure disparity d = f·b / z [px], so their noise is additive
// in inverse depth: 1/z_raw = 1/z + n, σ(n) = σ_d / (f·b) [1/m], the same at every depth. The device then
// stores depth in steps of q [m], uniform rounding of variance q²/12 in depth. Together
//   σ_z(z)² = (z² σ_d / (f·b))² + q²/12   [m²].
// Lateral noise. Where a pixel samples the surface also varies (the simulator jitters it, stereo matching
// shifts it on slanted surfaces, demosaicing and resampling blur colour): a shift of σ_px pixels adds
// (σ_px·‖∇s‖)² to the variance of a signal s with image gradient ∇s [per px], both for 1/z and for grey.
// Spatial correlation. Neighbouring pixels share noise (a projector dot's disparity fills its cell, stereo
// matches a window), so N pixels carry N / pixels_per_sample independent measurements, where
// pixels_per_sample = Σ_h ρ(h) over pixel lags h is the variance inflation of a mean over a large area; the
// correlation length is the lag [px] at which ρ falls to 1/e.

#include <cmath>

namespace vifusion {

struct DepthNoiseModel {
  double disparity_sigma_px = 0.0;   ///< σ_d: disparity noise [px], ≥ 0
  double focal_baseline_px_m = 0.0;  ///< f·b of the disparity d = f·b / z [px·m], > 0
  double quantisation_m = 0.0;       ///< q: depth output step [m], ≥ 0 (0: none)
  double lateral_sigma_px = 0.0;     ///< σ_px of where a pixel samples the surface [px], ≥ 0
  double correlation_px = 0.0;       ///< lag [px] at which the noise's correlation falls to 1/e, ≥ 0
  double pixels_per_sample = 1.0;    ///< Σ_h ρ(h): pixels per independent measurement, ≥ 1
  /// σ_b: the standard error of the rig's inverse-depth bias correction (calibration.yaml's
  /// inverse_depth_bias_per_m) [1/m], ≥ 0; 0 when unknown. Not noise: one error shared by every frame, which
  /// moves a point seen from z by σ_b·z², so surfaces fused from different distances disagree by it.
  double inverse_depth_bias_sigma_per_m = 0.0;

  /// σ of the noise on 1/z [1/m].
  double inverseDepthSigma() const { return disparity_sigma_px / focal_baseline_px_m; }
  /// σ_z at depth z_m [m] on a surface facing the camera (formula above, no lateral term).
  double depthSigma(double z_m) const {
    const double disparity_term = z_m * z_m * inverseDepthSigma();
    return std::sqrt(disparity_term * disparity_term + quantisation_m * quantisation_m / 12.0);
  }
};

struct IntensityNoiseModel {
  double sigma = 0.0;              ///< σ of the grey level (Rec. 601 luma of R, G, B) on the 0–255 scale, ≥ 0
  double lateral_sigma_px = 0.0;   ///< as DepthNoiseModel::lateral_sigma_px, for the grey image
  double correlation_px = 0.0;     ///< as DepthNoiseModel::correlation_px
  double pixels_per_sample = 1.0;  ///< as DepthNoiseModel::pixels_per_sample
};

struct CameraNoiseModel {
  DepthNoiseModel depth;
  IntensityNoiseModel intensity;
};

}  // namespace vifusion
