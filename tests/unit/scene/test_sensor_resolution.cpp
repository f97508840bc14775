#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "scene_views.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/sensor_noise.hpp"
#include "vifusion/scene/sensor_resolution.hpp"

namespace vifusion::scene {
namespace {

using test::pool;
using test::room;

/// The sim's 160×120 camera: ICL-NUIM's intrinsics for that image size (pixel centres at integers).
PinholeCamera quarterCamera() { return PinholeCamera::create(160, 120, 120.3, 120.0, 79.5, 59.5); }

/// Noisy depth [m] of `camera` at `view`, the way `vifusion sim` makes it: at the sensor's resolution
/// and subsampled when `camera` divides it, else at the camera's own pixels.
Image<float> noisyDepth(const PinholeCamera& camera, const SE3d& view, bool at_sensor_resolution) {
  const int s = at_sensor_resolution ? sensorSubsampling(camera) : 1;
  const PinholeCamera sensor = sensorCamera(camera, s);
  Image<Rgb8> rgb(sensor.width, sensor.height);
  Image<float> clean_m(sensor.width, sensor.height);
  Image<std::uint16_t> noisy(sensor.width, sensor.height);
  Renderer(room(), pool()).render(view, sensor, rgb.view(), clean_m.view());
  SensorNoiseOptions options;
  options.seed = 3;
  SensorNoise(options, pool()).addDepthNoise(clean_m.view(), noisy.view(), 0);
  Image<std::uint16_t> out(camera.width, camera.height);
  subsampleDepth(noisy.view(), s, out.view());
  Image<float> out_m(camera.width, camera.height);
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) out_m(x, y) = static_cast<float>(out(x, y) / options.depth_scale);
  }
  return out_m;
}

Image<float> cleanDepth(const PinholeCamera& camera, const SE3d& view) {
  Image<Rgb8> rgb(camera.width, camera.height);
  Image<float> depth_m(camera.width, camera.height);
  Renderer(room(), pool()).render(view, camera, rgb.view(), depth_m.view());
  return depth_m;
}

/// 1.4826 · median |noisy − clean| over pixels with both depths in [2.5, 3.5) m: a robust σ [m].
double robustSigma_m(const Image<float>& noisy_m, const Image<float>& clean_m) {
  std::vector<double> errors;
  for (int y = 0; y < clean_m.height(); ++y) {
    for (int x = 0; x < clean_m.width(); ++x) {
      if (noisy_m(x, y) > 0.0F && clean_m(x, y) >= 2.5F && clean_m(x, y) < 3.5F) {
        errors.push_back(std::abs(static_cast<double>(noisy_m(x, y)) - clean_m(x, y)));
      }
    }
  }
  EXPECT_GT(errors.size(), 200u);
  std::nth_element(errors.begin(), errors.begin() + errors.size() / 2, errors.end());
  return 1.4826 * errors[errors.size() / 2];
}

TEST(SensorResolution, SubsamplingOfTheSensorImage) {
  EXPECT_EQ(sensorSubsampling(test::iclCamera()), 1);
  EXPECT_EQ(sensorSubsampling(quarterCamera()), 4);
  EXPECT_EQ(sensorSubsampling(PinholeCamera::create(320, 240, 240.6, 240.0, 159.5, 119.5)), 2);
  EXPECT_EQ(sensorSubsampling(PinholeCamera::create(64, 48, 48.1, 48.0, 31.5, 23.5)), 10);
  // Not an integer subsampling of 640×480 (another aspect, or larger): noise at the camera's pixels.
  EXPECT_EQ(sensorSubsampling(PinholeCamera::create(320, 200, 240.6, 240.0, 159.5, 99.5)), 1);
  EXPECT_EQ(sensorSubsampling(PinholeCamera::create(1280, 960, 962.4, 960.0, 639.5, 479.5)), 1);
  EXPECT_EQ(sensorSubsampling(PinholeCamera::create(300, 225, 225.0, 225.0, 149.5, 112.0)), 1);

  Image<std::uint16_t> native(8, 6);
  for (int y = 0; y < 6; ++y) {
    for (int x = 0; x < 8; ++x) native(x, y) = static_cast<std::uint16_t>(100 * y + x);
  }
  Image<std::uint16_t> out(4, 3);
  subsampleDepth(native.view(), 2, out.view());
  EXPECT_EQ(out(0, 0), 0);
  EXPECT_EQ(out(3, 2), 406);
  Image<std::uint16_t> wrong(3, 3);
  EXPECT_THROW(subsampleDepth(native.view(), 2, wrong.view()), std::invalid_argument);
}

TEST(SensorResolution, SubsampledNoiseIsTheNativeNoiseAtTheKeptPixels) {
  // `vifusion sim` runs step 4 only at the pixels it keeps; every kept value must be the full image's, bit for bit
  // (the draws are indexed by the sensor's pixel), on a furnished view over several frames and both subsamplings.
  const PinholeCamera sensor = test::iclCamera();
  Image<Rgb8> rgb(sensor.width, sensor.height);
  Image<float> clean_m(sensor.width, sensor.height);
  Renderer(room(), pool()).render(test::furnishedView(), sensor, rgb.view(), clean_m.view());
  SensorNoiseOptions options;
  options.seed = 5;
  SensorNoise noise(options, pool());
  Image<std::uint16_t> full(sensor.width, sensor.height);
  for (const int s : {2, 4}) {
    Image<std::uint16_t> reference(sensor.width / s, sensor.height / s);
    Image<std::uint16_t> kept(sensor.width / s, sensor.height / s);
    for (const std::uint64_t frame : {0u, 1u, 17u}) {
      noise.addDepthNoise(clean_m.view(), full.view(), frame);
      subsampleDepth(full.view(), s, reference.view());
      noise.addDepthNoise(clean_m.view(), kept.view(), frame, s);
      int differing = 0, valid = 0;
      for (int y = 0; y < kept.height(); ++y) {
        for (int x = 0; x < kept.width(); ++x) {
          differing += kept(x, y) != reference(x, y);
          valid += kept(x, y) != 0;
        }
      }
      EXPECT_EQ(differing, 0) << "subsampling " << s << ", frame " << frame;
      EXPECT_GT(valid, kept.width() * kept.height() / 2) << "subsampling " << s << ", frame " << frame;
    }
  }
  Image<std::uint16_t> wrong(sensor.width / 4 + 1, sensor.height / 4);
  EXPECT_THROW(noise.addDepthNoise(clean_m.view(), wrong.view(), 0, 4), std::invalid_argument);
  EXPECT_THROW(noise.addDepthNoise(clean_m.view(), full.view(), 0, 0), std::invalid_argument);
}

TEST(SensorResolution, NativePixelsSeeTheRaysOfTheSubsampledOnes) {
  // Clean depth: the sensor camera's pixel (4x, 4y) must see what the 160×120 camera sees at (x, y).
  const PinholeCamera camera = quarterCamera();
  const PinholeCamera sensor = sensorCamera(camera, 4);
  const Image<float> direct = cleanDepth(camera, test::furnishedView());
  const Image<float> native = cleanDepth(sensor, test::furnishedView());
  int compared = 0, equal = 0;
  for (int y = 0; y < camera.height; ++y) {
    for (int x = 0; x < camera.width; ++x) {
      if (direct(x, y) <= 0.0F) continue;
      ++compared;
      if (std::abs(direct(x, y) - native(4 * x, 4 * y)) < 1e-4F) ++equal;
    }
  }
  ASSERT_GT(compared, 10000);
  // Depth edges may differ by the renderer's sub-pixel edge handling; everything else is the same ray.
  EXPECT_GT(static_cast<double>(equal) / compared, 0.97) << equal << " of " << compared;
}

TEST(SensorResolution, SmallImagesHaveTheSensorsNoise) {
  const SE3d view = test::furnishedView();
  const double sigma_640_m =
      robustSigma_m(noisyDepth(test::iclCamera(), view, true), cleanDepth(test::iclCamera(), view));
  const PinholeCamera camera = quarterCamera();
  const Image<float> clean_m = cleanDepth(camera, view);
  const double sigma_subsampled_m = robustSigma_m(noisyDepth(camera, view, true), clean_m);
  const double sigma_direct_m = robustSigma_m(noisyDepth(camera, view, false), clean_m);
  std::printf(
      "depth noise at 2.5-3.5 m (robust sigma): 640x480 %.1f mm, 160x120 subsampled %.1f mm, "
      "160x120 noise applied at its own pixels %.1f mm\n",
      1e3 * sigma_640_m, 1e3 * sigma_subsampled_m, 1e3 * sigma_direct_m);
  EXPECT_NEAR(sigma_subsampled_m, sigma_640_m, 0.25 * sigma_640_m);
  // What the subsampling avoids: the model's pixel-sized steps on 4× larger pixels.
  EXPECT_GT(sigma_direct_m, 1.5 * sigma_640_m);
}

}  // namespace
}  // namespace vifusion::scene
