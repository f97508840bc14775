#include "vifusion/map/map_buffers.hpp"

#include <cstring>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::map {

MapBuffers::MapBuffers(gpu::CapacityPlan& plan, const MapOptions& options, const PinholeCamera& camera)
    : options_(options), width_(camera.width), height_(camera.height) {
  options_.validate();
  if (width_ <= 0 || height_ <= 0) throw Error("map buffers: camera image size is not set");
  const uint64_t surfel_bytes = uint64_t{options_.capacity} * sizeof(Surfel);
  const uint64_t pixel_bytes = uint64_t(width_) * uint64_t(height_) * sizeof(std::uint32_t);
  surfels_[0] = plan.addBuffer("map.surfels0", surfel_bytes, gpu::MemoryUse::DeviceLocal);
  surfels_[1] = plan.addBuffer("map.surfels1", surfel_bytes, gpu::MemoryUse::DeviceLocal);
  // Upload memory is host-visible and coherent: the host reads the count after a frame without a copy.
  state_ = plan.addBuffer("map.state", sizeof(MapState), gpu::MemoryUse::Upload);
  index_depth_ = plan.addBuffer("map.index_depth", pixel_bytes, gpu::MemoryUse::DeviceLocal);
  index_id_ = plan.addBuffer("map.index_id", pixel_bytes, gpu::MemoryUse::DeviceLocal);
}

MapState MapBuffers::readState(const gpu::MemoryArena& arena) const {
  MapState state;
  std::memcpy(&state, arena.buffer(state_).mapped, sizeof(state));
  return state;
}

void MapBuffers::reset(const gpu::MemoryArena& arena) {
  const MapState empty;
  std::memcpy(arena.buffer(state_).mapped, &empty, sizeof(empty));
  current_ = 0;
}

void MapBuffers::setLoaded(const gpu::MemoryArena& arena, std::uint32_t surfel_count, std::uint32_t frame) const {
  MapState state;
  state.surfel_count = surfel_count;
  state.frame = frame;
  state.active_begin = 0;
  std::memcpy(arena.buffer(state_).mapped, &state, sizeof(state));
}

void MapBuffers::visitWholeMapNextFrame(const gpu::MemoryArena& arena) const {
  MapState state = readState(arena);
  state.active_begin = 0;
  std::memcpy(arena.buffer(state_).mapped, &state, sizeof(state));
}

void MapBuffers::shrinkInactivePrefix(const gpu::MemoryArena& arena, std::uint32_t active_begin) const {
  MapState state = readState(arena);
  if (active_begin > state.active_begin) throw Error("map buffers: the inactive prefix can only shrink");
  state.active_begin = active_begin;
  std::memcpy(arena.buffer(state_).mapped, &state, sizeof(state));
}

}  // namespace vifusion::map
