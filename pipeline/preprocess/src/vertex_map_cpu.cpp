// CPU reference of shaders/vertex_map.comp.

#include "view_checks.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"

namespace vifusion::preprocess {

void vertexMapCpu(ImageView<const float> depth_m, const VertexMapParams& params, ImageView<VertexPixel> vertices) {
  detail::requireSize(depth_m, params.width, params.height, "vertexMapCpu", "depth_m");
  detail::requireSize(vertices, params.width, params.height, "vertexMapCpu", "vertices");
  for (int v = 0; v < params.height; ++v) {
    for (int u = 0; u < params.width; ++u) {
      const float z_m = depth_m(u, v);
      if (!(z_m > 0.0f)) {
        vertices(u, v) = VertexPixel::Zero();
        continue;
      }
      // Divide, then multiply, as the shader does (not z/fx first): same rounding on both sides.
      const float x_m = (static_cast<float>(u) - params.cx) / params.fx * z_m;
      const float y_m = (static_cast<float>(v) - params.cy) / params.fy * z_m;
      vertices(u, v) = VertexPixel(x_m, y_m, z_m, 1.0f);
    }
  }
}

}  // namespace vifusion::preprocess
