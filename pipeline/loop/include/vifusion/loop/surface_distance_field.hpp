#pragma once
// The distance from any point of a saved map's space to its nearest surface, on a voxel grid: what lets a frame be
// scored against the whole map at thousands of poses without rendering it (global_place_search.hpp) — the
// "likelihood field" of laser localisation (Thrun, Burgard, Fox, Probabilistic Robotics §6.4) in 3-D.
//
// Built once from the map's surface points (stable surfel centres, in W): a voxel holding a point is a surface
// voxel; every voxel then holds the Euclidean distance between its centre and the nearest surface voxel's centre,
// computed exactly by the separable squared-distance transform of Felzenszwalb and Huttenlocher ("Distance
// transforms of sampled functions", Theory of Computing 2012) along x, y and z. Queries interpolate trilinearly,
// so the distance is continuous and has a gradient for Gauss-Newton. Quantisation: a query's distance can be off
// by up to half a voxel diagonal (√3/2 · voxel_size_m) against the true distance to the points.
//
// The grid is axis-aligned in W and covers the points' bounding box padded by `padding_m` on every side; a query
// outside it has no distance (infinity). Memory is 4 bytes per voxel, bounded by max_voxels: a map whose box
// needs more voxels at voxel_size_m gets proportionally larger voxels (the coarser field is still a valid
// distance, only less precise).

#include <Eigen/Core>
#include <cstdint>
#include <span>
#include <vector>

namespace vifusion::loop {

struct DistanceFieldOptions {
  /// Edge of a voxel [m]. > 0. Smaller is more precise (quantisation √3/2 of it) at the cube of the memory.
  double voxel_size_m = 0.05;
  /// The grid extends this far beyond the points' bounding box [m], so points just off the map's outer surfaces
  /// still get their distance. ≥ 0.
  double padding_m = 0.5;
  /// Most voxels the grid may hold (4 bytes each): 16 M is 64 MiB. [1, 2^31).
  std::int64_t max_voxels = 16'000'000;

  /// @throws vifusion::Error naming the field out of range.
  void validate() const;
};

class SurfaceDistanceField {
 public:
  SurfaceDistanceField() = default;
  /// Builds the field of `points_W` (non-finite points are skipped). Allocates (once, at map load).
  /// @throws vifusion::Error when no point is finite or an option is out of range
  SurfaceDistanceField(std::span<const Eigen::Vector3f> points_W, const DistanceFieldOptions& options);

  bool empty() const { return distances_m_.empty(); }
  /// Distance [m] from p_W to the nearest surface (trilinear between voxel centres); infinity outside the grid.
  /// @param[out] gradient_W  when not null and the distance is finite: ∂distance/∂p_W [1] (that of the
  ///                         interpolation, so piecewise smooth)
  double distance(const Eigen::Vector3d& p_W, Eigen::Vector3d* gradient_W = nullptr) const;

  double voxelSize() const { return voxel_size_m_; }           ///< [m] (after any coarsening for max_voxels)
  const Eigen::Vector3d& minCorner() const { return min_W_; }  ///< the grid's first voxel centre in W [m]
  Eigen::Vector3d maxCorner() const;                           ///< its last voxel centre in W [m]
  Eigen::Vector3i dimensions() const { return size_; }         ///< voxels along x, y, z
  std::int64_t surfaceVoxels() const { return surface_voxels_; }

 private:
  float at(int x, int y, int z) const {
    return distances_m_[(static_cast<std::size_t>(z) * size_.y() + y) * size_.x() + x];
  }

  double voxel_size_m_ = 0.0;
  Eigen::Vector3d min_W_ = Eigen::Vector3d::Zero();
  Eigen::Vector3i size_ = Eigen::Vector3i::Zero();
  std::int64_t surface_voxels_ = 0;
  std::vector<float> distances_m_;  ///< x fastest, then y, then z
};

}  // namespace vifusion::loop
