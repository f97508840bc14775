#include "vifusion/loop/surface_distance_field.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {
namespace {

/// "No surface on this line yet" in the squared-distance transform [voxels²]: far beyond any real squared
/// distance of a grid within max_voxels (< 2^31 voxels, so < 2^62 voxels² along the diagonal) and finite, so
/// the transform's parabola intersections stay defined.
constexpr double kFar = 1e30;

/// One line of the exact 1-D squared-distance transform (Felzenszwalb & Huttenlocher 2012, §2.1):
/// out[q] = min over p of (q − p)² + in[p]. `hull` (n ints) and `bounds` (n + 1 doubles) are scratch.
void squaredDistanceLine(const double* in, int n, double* out, int* hull, double* bounds) {
  int k = 0;
  hull[0] = 0;
  bounds[0] = -std::numeric_limits<double>::infinity();
  bounds[1] = std::numeric_limits<double>::infinity();
  const auto intersection = [in](int q, int p) {
    return ((in[q] + double(q) * q) - (in[p] + double(p) * p)) / (2.0 * (q - p));
  };
  for (int q = 1; q < n; ++q) {
    double s = intersection(q, hull[k]);
    while (s <= bounds[k]) s = intersection(q, hull[--k]);  // stops at k = 0: bounds[0] = −∞, s is finite
    ++k;
    hull[k] = q;
    bounds[k] = s;
    bounds[k + 1] = std::numeric_limits<double>::infinity();
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (bounds[k + 1] < q) ++k;
    const double d = q - hull[k];
    out[q] = d * d + in[hull[k]];
  }
}

}  // namespace

void DistanceFieldOptions::validate() const {
  if (!(voxel_size_m > 0.0) || !std::isfinite(voxel_size_m))
    throw Error("distance field option 'voxel_size_m' = " + std::to_string(voxel_size_m) + " must be > 0");
  if (!(padding_m >= 0.0) || !std::isfinite(padding_m))
    throw Error("distance field option 'padding_m' = " + std::to_string(padding_m) + " must be >= 0");
  if (max_voxels < 1 || max_voxels >= (std::int64_t{1} << 31))
    throw Error("distance field option 'max_voxels' = " + std::to_string(max_voxels) + " must be in [1, 2^31)");
}

SurfaceDistanceField::SurfaceDistanceField(std::span<const Eigen::Vector3f> points_W,
                                           const DistanceFieldOptions& options) {
  options.validate();
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector3d hi = -lo;
  for (const Eigen::Vector3f& p : points_W) {
    if (!p.allFinite()) continue;
    lo = lo.cwiseMin(p.cast<double>());
    hi = hi.cwiseMax(p.cast<double>());
  }
  if (!lo.allFinite()) throw Error("distance field: no finite surface point to build it from");
  lo.array() -= options.padding_m;
  hi.array() += options.padding_m;
  const Eigen::Vector3d extent = hi - lo;
  voxel_size_m_ = options.voxel_size_m;
  const auto voxelsAt = [&extent](double size) {
    return Eigen::Vector3i(((extent / size).array().floor() + 1.0).cast<int>().matrix());
  };
  size_ = voxelsAt(voxel_size_m_);
  const auto count = [](const Eigen::Vector3i& s) { return std::int64_t{s.x()} * s.y() * s.z(); };
  while (count(size_) > options.max_voxels) {
    voxel_size_m_ *= std::cbrt(static_cast<double>(count(size_)) / options.max_voxels) * 1.01;
    size_ = voxelsAt(voxel_size_m_);
  }
  min_W_ = lo;

  std::vector<double> squared(static_cast<std::size_t>(count(size_)), kFar);
  const auto index = [this](int x, int y, int z) {
    return (static_cast<std::size_t>(z) * size_.y() + y) * size_.x() + x;
  };
  for (const Eigen::Vector3f& p : points_W) {
    if (!p.allFinite()) continue;
    const Eigen::Vector3i v = ((p.cast<double>() - min_W_) / voxel_size_m_).array().round().cast<int>();
    double& cell = squared[index(std::clamp(v.x(), 0, size_.x() - 1), std::clamp(v.y(), 0, size_.y() - 1),
                                 std::clamp(v.z(), 0, size_.z() - 1))];
    if (cell != 0.0) ++surface_voxels_;
    cell = 0.0;
  }

  // Separable: transform every line along x, then along y, then along z.
  const int longest = size_.maxCoeff();
  std::vector<double> line_in(longest), line_out(longest), bounds(longest + 1);
  std::vector<int> hull(longest);
  const std::array<int, 3> strides = {1, size_.x(), size_.x() * size_.y()};
  for (int axis = 0; axis < 3; ++axis) {
    const int n = size_[axis];
    const int a = (axis + 1) % 3, b = (axis + 2) % 3;  // the two other axes span the lines' starts
    for (int j = 0; j < size_[b]; ++j) {
      for (int i = 0; i < size_[a]; ++i) {
        const std::size_t start = static_cast<std::size_t>(i) * strides[a] + static_cast<std::size_t>(j) * strides[b];
        for (int q = 0; q < n; ++q) line_in[q] = squared[start + static_cast<std::size_t>(q) * strides[axis]];
        squaredDistanceLine(line_in.data(), n, line_out.data(), hull.data(), bounds.data());
        for (int q = 0; q < n; ++q) squared[start + static_cast<std::size_t>(q) * strides[axis]] = line_out[q];
      }
    }
  }
  distances_m_.resize(squared.size());
  for (std::size_t i = 0; i < squared.size(); ++i) {
    distances_m_[i] = static_cast<float>(std::sqrt(squared[i]) * voxel_size_m_);
  }
}

Eigen::Vector3d SurfaceDistanceField::maxCorner() const {
  return min_W_ + voxel_size_m_ * (size_ - Eigen::Vector3i::Ones()).cast<double>();
}

double SurfaceDistanceField::distance(const Eigen::Vector3d& p_W, Eigen::Vector3d* gradient_W) const {
  const Eigen::Vector3d g = (p_W - min_W_) / voxel_size_m_;  // in voxel units from the first centre
  if (!(g.minCoeff() >= 0.0) || !(g.x() <= size_.x() - 1) || !(g.y() <= size_.y() - 1) || !(g.z() <= size_.z() - 1)) {
    return std::numeric_limits<double>::infinity();
  }
  // The cell's lower corner, kept one below the last centre so its +1 neighbours exist.
  const int x = std::min(static_cast<int>(g.x()), std::max(0, size_.x() - 2));
  const int y = std::min(static_cast<int>(g.y()), std::max(0, size_.y() - 2));
  const int z = std::min(static_cast<int>(g.z()), std::max(0, size_.z() - 2));
  const int x1 = std::min(x + 1, size_.x() - 1), y1 = std::min(y + 1, size_.y() - 1),
            z1 = std::min(z + 1, size_.z() - 1);
  const double fx = g.x() - x, fy = g.y() - y, fz = g.z() - z;
  const double c000 = at(x, y, z), c100 = at(x1, y, z), c010 = at(x, y1, z), c110 = at(x1, y1, z);
  const double c001 = at(x, y, z1), c101 = at(x1, y, z1), c011 = at(x, y1, z1), c111 = at(x1, y1, z1);
  const double c00 = c000 + fx * (c100 - c000), c10 = c010 + fx * (c110 - c010);
  const double c01 = c001 + fx * (c101 - c001), c11 = c011 + fx * (c111 - c011);
  const double c0 = c00 + fy * (c10 - c00), c1 = c01 + fy * (c11 - c01);
  if (gradient_W != nullptr) {
    const double dx0 = (1 - fy) * (c100 - c000) + fy * (c110 - c010);
    const double dx1 = (1 - fy) * (c101 - c001) + fy * (c111 - c011);
    const double dy0 = c10 - c00, dy1 = c11 - c01;
    *gradient_W = Eigen::Vector3d((1 - fz) * dx0 + fz * dx1, (1 - fz) * dy0 + fz * dy1, c1 - c0) / voxel_size_m_;
  }
  return c0 + fz * (c1 - c0);
}

}  // namespace vifusion::loop
