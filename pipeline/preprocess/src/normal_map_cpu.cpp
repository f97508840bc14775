// CPU reference of shaders/normal_map.comp. The cross product and norms are written out component
// by component in the shader's order rather than with Eigen's cross()/normalized(), whose internal
// order (and vectorisation) is not specified.

#include <cmath>
#include <stdexcept>

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {
namespace {

bool isValidVertex(const VertexPixel& vertex_m) { return vertex_m.z() > 0.0f; }

}  // namespace

void normalMapCpu(ImageView<const VertexPixel> vertices, const NormalMapParams& params,
                  ImageView<NormalPixel> normals) {
  detail::requireSize(vertices, params.width, params.height, "normalMapCpu", "vertices");
  detail::requireSize(normals, params.width, params.height, "normalMapCpu", "normals");
  if (params.span_px < 1) throw std::invalid_argument("normalMapCpu: span_px must be ≥ 1");
  const float min_norm_sq = params.min_cross_norm_m2 * params.min_cross_norm_m2;
  const int s = params.span_px;

  for (int y = 0; y < params.height; ++y) {
    for (int x = 0; x < params.width; ++x) {
      normals(x, y) = NormalPixel::Zero();
      if (x < s || y < s || x + s >= params.width || y + s >= params.height) continue;
      const VertexPixel& v = vertices(x, y);
      const VertexPixel& left = vertices(x - s, y);
      const VertexPixel& right = vertices(x + s, y);
      const VertexPixel& above = vertices(x, y - s);
      const VertexPixel& below = vertices(x, y + s);
      if (!isValidVertex(v) || !isValidVertex(left) || !isValidVertex(right) || !isValidVertex(above) ||
          !isValidVertex(below)) {
        continue;
      }

      const float ax = right.x() - left.x();
      const float ay = right.y() - left.y();
      const float az = right.z() - left.z();
      const float bx = below.x() - above.x();
      const float by = below.y() - above.y();
      const float bz = below.z() - above.z();
      const float cross_x = ay * bz - az * by;
      const float cross_y = az * bx - ax * bz;
      const float cross_z = ax * by - ay * bx;
      const float norm_sq = cross_x * cross_x + cross_y * cross_y + cross_z * cross_z;
      if (norm_sq < min_norm_sq) continue;

      const float norm = std::sqrt(norm_sq);
      float nx = cross_x / norm;
      float ny = cross_y / norm;
      float nz = cross_z / norm;
      if (nx * v.x() + ny * v.y() + nz * v.z() > 0.0f) {
        nx = -nx;
        ny = -ny;
        nz = -nz;
      }
      normals(x, y) = NormalPixel(nx, ny, nz, 1.0f);
    }
  }
}

}  // namespace vifusion::preprocess
