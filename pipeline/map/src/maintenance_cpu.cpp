#include "vifusion/map/maintenance_cpu.hpp"

#include <algorithm>
#include <bit>
#include <cmath>

namespace vifusion::map {
namespace {

// violatesFreeSpace of map_cleanup.comp, operation for operation.
bool violatesFreeSpace(std::size_t i, const Surfel& surfel, std::span<const Surfel> surfels,
                       const CleanupParams& params, ImageView<const std::uint32_t> index_depth,
                       ImageView<const std::uint32_t> index_id) {
  const MapView& view = params.view;
  const Eigen::Vector3f p_C = transformPointCpu(view, surfel.position_confidence.head<3>());
  if (!(p_C.z() > 0.0f && p_C.z() <= params.max_depth_m)) return false;
  const Eigen::Vector3f n_C = rotateVectorCpu(view, surfel.normal_radius.head<3>());
  if (!(std::abs(n_C.z()) > params.facing_min_abs_nz)) return false;
  const Eigen::Vector2f uv = projectPointCpu(view, p_C);
  const float centre_x = std::floor(uv.x() + 0.5f);
  const float centre_y = std::floor(uv.y() + 0.5f);
  if (!(centre_x >= 0.0f && centre_x < static_cast<float>(view.width) && centre_y >= 0.0f &&
        centre_y < static_cast<float>(view.height))) {
    return false;
  }
  const int px = static_cast<int>(centre_x);
  const int py = static_cast<int>(centre_y);
  const auto count = static_cast<std::uint32_t>(surfels.size());
  std::uint32_t behind = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int qx = px + dx;
      const int qy = py + dy;
      if (!index_id.contains(qx, qy)) continue;
      const std::uint32_t id = index_id(qx, qy);
      if (id == 0u || id - 1u == i || id - 1u >= count) continue;
      const Surfel& other = surfels[id - 1u];
      if (other.position_confidence.w() < params.confidence_threshold) continue;
      if (static_cast<std::uint32_t>(other.colour_times.z()) != view.frame) continue;
      const float gap_m = std::bit_cast<float>(index_depth(qx, qy)) - p_C.z();
      if (gap_m > params.free_space_margin_m) ++behind;
    }
  }
  return behind >= params.free_space_min_neighbours;
}

}  // namespace

std::uint32_t nextEvictionAge(std::uint32_t age_frames, std::uint32_t surfel_count, std::uint32_t full_count,
                              std::uint32_t frame, std::uint32_t time_window_frames) {
  if (surfel_count <= full_count) return kNoAgeEviction;
  return std::max(time_window_frames, std::min(age_frames, frame) / 2);
}

void cleanupCpu(std::span<const Surfel> surfels, std::uint32_t active_begin, const CleanupParams& params,
                ImageView<const std::uint32_t> index_depth, ImageView<const std::uint32_t> index_id,
                std::span<std::uint32_t> keep, std::span<std::uint32_t> retire, MaintenanceStats& stats) {
  const auto count = static_cast<std::uint32_t>(surfels.size());
  for (std::size_t i = active_begin; i < surfels.size(); ++i) {
    const Surfel& surfel = surfels[i];
    const float confidence = surfel.position_confidence.w();
    const std::uint32_t age = framesSinceCpu(params.view, surfel.colour_times.z());
    std::uint32_t flag = 1;
    std::uint32_t retired = 0;
    if (age > params.time_window_frames) {
      flag = 0;
      if (count > params.full_count && (confidence < params.eviction_confidence || age > params.eviction_age_frames)) {
        ++stats.evicted_when_full;
      } else {
        retired = 1;
        ++stats.retired;
      }
    } else if (confidence < params.confidence_threshold && age > params.unstable_max_age_frames) {
      flag = 0;
      ++stats.removed_unstable;
    } else if (violatesFreeSpace(i, surfel, surfels, params, index_depth, index_id)) {
      flag = 0;
      ++stats.removed_free_space;
    }
    keep[i - active_begin] = flag;
    retire[i - active_begin] = retired;
  }
}

std::uint32_t exclusiveScanCpu(std::span<const std::uint32_t> values, std::span<std::uint32_t> offsets) {
  std::uint32_t running = 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    offsets[i] = running;
    running += values[i];
  }
  return running;
}

MapExtent compactCpu(std::span<const Surfel> surfels, std::uint32_t active_begin, std::span<const std::uint32_t> keep,
                     std::span<const std::uint32_t> retire, std::span<Surfel> destination) {
  std::uint32_t next = active_begin;
  std::copy(surfels.begin(), surfels.begin() + active_begin, destination.begin());
  for (std::size_t i = active_begin; i < surfels.size(); ++i) {
    if (retire[i - active_begin] != 0u) destination[next++] = surfels[i];
  }
  MapExtent extent;
  extent.active_begin = next;
  for (std::size_t i = active_begin; i < surfels.size(); ++i) {
    if (retire[i - active_begin] == 0u && keep[i - active_begin] != 0u) destination[next++] = surfels[i];
  }
  extent.surfel_count = next;
  return extent;
}

}  // namespace vifusion::map
