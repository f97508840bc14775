#pragma once
// CPU reference of shaders/rotation_reduce.comp: same homography, gates, bilinear sampling, residuals,
// Jacobians and weights in float, summed in double.

#include "vifusion/core/image.hpp"
#include "vifusion/preprocess/pixel_types.hpp"
#include "vifusion/reduction/normal_equations.hpp"
#include "vifusion/tracking/rotation_params.hpp"

namespace vifusion::tracking {

NormalEquations6 rotationNormalEquationsCpu(ImageView<const float> current_intensity,
                                            ImageView<const float> previous_intensity,
                                            ImageView<const preprocess::GradientPixel> previous_gradients,
                                            const RotationParams& params);

}  // namespace vifusion::tracking
