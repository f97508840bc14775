#include "rendered_pan.hpp"

#include <cmath>
#include <cstdint>

#include "vifusion/core/image.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/look_at.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/row_pool.hpp"

namespace vifusion::test {

Pan renderPan(const PinholeCamera& camera) { return renderPan(camera, DepthCameraCalibration{camera, SE3d()}); }

Pan renderPan(const PinholeCamera& camera, const DepthCameraCalibration& depth) {
  const scene::LivingRoom room;
  scene::RowPool pool(2);
  const scene::Renderer renderer(room, pool);
  Pan pan;
  Image<float> depth_m(camera.width, camera.height);
  Image<Rgb8> unused_rgb(camera.width, camera.height);
  for (int i = 0; i < 40; ++i) {
    const double yaw_rad = 0.004 * i;
    const Eigen::Vector3d eye_W(1.1 + 0.002 * i, 1.3, 0.8);
    const Eigen::Vector3d target_W = eye_W + Eigen::Vector3d(std::sin(yaw_rad), -0.25, -std::cos(yaw_rad));
    RgbdFrame frame;
    frame.depth = Image<std::uint16_t>(camera.width, camera.height);
    frame.rgb = Image<Rgb8>(camera.width, camera.height);
    frame.depth_scale_m = 0.001;
    pan.T_W_C.push_back(scene::lookAt(eye_W, target_W));
    renderer.render(pan.T_W_C.back(), camera, frame.rgb.view(), depth_m.view());
    if (!(depth.T_C_D.log().norm() == 0.0 && depth.camera.fx == camera.fx && depth.camera.cx == camera.cx)) {
      renderer.render(pan.T_W_C.back() * depth.T_C_D, depth.camera, unused_rgb.view(), depth_m.view());
    }
    for (int y = 0; y < camera.height; ++y) {
      for (int x = 0; x < camera.width; ++x) {
        frame.depth(x, y) = static_cast<std::uint16_t>(std::lround(depth_m(x, y) * 1000.0f));
      }
    }
    pan.frames.push_back(std::move(frame));
  }
  return pan;
}

std::size_t panFrameIndex(std::size_t step, std::size_t pan_frames) {
  const std::size_t period = 2 * (pan_frames - 1);
  const std::size_t k = step % period;
  return k < pan_frames ? k : period - k;
}

RigCalibration panCalibration() {
  RigCalibration calibration;
  calibration.camera = PinholeCamera::create(160, 120, 120.0, 120.0, 79.5, 59.5);
  calibration.depth_scale_m = 0.001;
  return calibration;
}

}  // namespace vifusion::test
