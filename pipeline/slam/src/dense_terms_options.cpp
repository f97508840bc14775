#include "vifusion/slam/dense_terms_options.hpp"

#include "vifusion/core/error.hpp"

namespace vifusion::slam {

void DenseTermsOptions::validate() const {
  if (!(information_scale > 0.0 && information_scale <= 1.0)) {
    throw Error("dense-terms option 'information_scale' must be in (0, 1]");
  }
  if (!(icp_min_constraint_share >= 0.0 && icp_min_constraint_share < 1.0 / 3.0)) {
    throw Error("dense-terms option 'icp_min_constraint_share' must be in [0, 1/3)");
  }
}

}  // namespace vifusion::slam
