#pragma once
// CPU reference of shaders/photometric_reduce.comp: same association, gates, bilinear sampling,
// residuals, Jacobians and weights in float, summed in double.

#include "vifusion/core/image.hpp"
#include "vifusion/preprocess/pixel_types.hpp"
#include "vifusion/reduction/normal_equations.hpp"
#include "vifusion/tracking/photometric_params.hpp"

namespace vifusion::tracking {

NormalEquations6 photometricNormalEquationsCpu(ImageView<const preprocess::VertexPixel> current_vertices,
                                               ImageView<const float> current_intensity,
                                               ImageView<const float> reference_intensity,
                                               ImageView<const preprocess::GradientPixel> reference_gradients,
                                               ImageView<const preprocess::VertexPixel> reference_vertices,
                                               const PhotometricParams& params);

}  // namespace vifusion::tracking
