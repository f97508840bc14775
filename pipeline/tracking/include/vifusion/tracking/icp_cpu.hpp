#pragma once
// CPU reference of shaders/icp_reduce.comp: the same association, gates, residuals, Jacobians and
// weights in float, summed in double.

#include "vifusion/core/image.hpp"
#include "vifusion/preprocess/pixel_types.hpp"
#include "vifusion/reduction/normal_equations.hpp"
#include "vifusion/tracking/icp_params.hpp"

namespace vifusion::tracking {

/// current_* in the current camera frame, model_* in the reference camera frame, all of
/// params.width × params.height. Rows are [J (1×6), r] for T_ref_cur ← exp(δ)·T_ref_cur.
NormalEquations6 icpNormalEquationsCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                                       ImageView<const preprocess::NormalPixel> current_normals,
                                       ImageView<const preprocess::VertexPixel> model_vertices,
                                       ImageView<const preprocess::NormalPixel> model_normals, const IcpParams& params);

}  // namespace vifusion::tracking
