#pragma once
// How the dense tracker's terms enter the two-state RGB-D-inertial estimator (tracker_dense_terms.hpp).

namespace vifusion::slam {

struct DenseTermsOptions {
  /// Weight of the dense terms' information against the IMU's, in (0, 1]. The tracker weights each pixel
  /// by its own noise as if pixels were independent; they are not (one projector dot's disparity fills a
  /// 3×3-pixel patch, depth is quantised in bands, the map's errors span whole surfaces), so N pixels
  /// carry far less than N measurements, and unscaled the dense terms outvote the IMU wherever they are
  /// biased. Measured at 320×240 with one value for every sequence: white_wall ATE 63 mm at 0.03, 25 mm
  /// at 0.01, 20 mm at 0.003 (at 1 it runs away); 10 s of living_room_0 7.8, 10.2 and 18.2 mm (6.9 at 1).
  double information_scale = 0.01;
  /// ICP translation directions with less than this share of the ICP weight are removed first
  /// (tracking/icp_degeneracy.hpp: blank wall 0.0003–0.003, wall and ceiling 0.004–0.009, furnished
  /// views ≥ 0.05). In [0, 1/3); 0 removes nothing.
  double icp_min_constraint_share = 0.02;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

}  // namespace vifusion::slam
