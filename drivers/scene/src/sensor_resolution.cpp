#include "vifusion/scene/sensor_resolution.hpp"

#include <stdexcept>
#include <string>

namespace vifusion::scene {

int sensorSubsampling(const PinholeCamera& camera) {
  if (camera.width <= 0 || camera.height <= 0 || kSensorWidth % camera.width != 0) return 1;
  const int s = kSensorWidth / camera.width;
  return s * camera.height == kSensorHeight ? s : 1;
}

PinholeCamera sensorCamera(const PinholeCamera& camera, int subsampling) {
  if (subsampling < 1) throw std::invalid_argument("sensorCamera: subsampling must be >= 1");
  const double s = subsampling;
  return PinholeCamera{.width = camera.width * subsampling,
                       .height = camera.height * subsampling,
                       .fx = camera.fx * s,
                       .fy = camera.fy * s,
                       .cx = camera.cx * s,
                       .cy = camera.cy * s};
}

void subsampleDepth(ImageView<const std::uint16_t> native, int subsampling, ImageView<std::uint16_t> out) {
  if (subsampling < 1 || native.width != out.width * subsampling || native.height != out.height * subsampling) {
    throw std::invalid_argument("subsampleDepth: native image " + std::to_string(native.width) + "x" +
                                std::to_string(native.height) + " is not " + std::to_string(subsampling) +
                                " times the output " + std::to_string(out.width) + "x" + std::to_string(out.height));
  }
  for (int y = 0; y < out.height; ++y) {
    const std::uint16_t* source = native.row(y * subsampling);
    std::uint16_t* target = out.row(y);
    for (int x = 0; x < out.width; ++x) target[x] = source[x * subsampling];
  }
}

}  // namespace vifusion::scene
