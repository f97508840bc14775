#pragma once
// CPU references of the surfel fusion kernels (shaders/map_index.comp, map_associate.comp,
// map_fuse.comp, map_insert.comp), same float arithmetic in the same order, used by the GPU
// tests. Each function is one kernel (all passes of it), so a test can feed every kernel the GPU's
// own input and compare that kernel alone.

#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/map/fusion_params.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/surfel.hpp"
#include "vifusion/preprocess/pixel_types.hpp"

namespace vifusion::map {

/// The current frame as the fusion kernels read it: level-0 camera-frame maps and the packed
/// RGB888 upload (preprocess/packing.hpp), all params.width × params.height.
struct MeasurementMaps {
  ImageView<const preprocess::VertexPixel> vertices;
  ImageView<const preprocess::NormalPixel> normals;
  std::span<const std::uint32_t> rgb_words;
};

/// map_index, both passes: fills index_depth (0xFFFFFFFF = empty) and index_id (0 = empty) from
/// surfels [0, surfel_count). Both spans hold width × height entries.
void indexMapCpu(std::span<const Surfel> surfels, std::uint32_t surfel_count, const FusionParams& params,
                 std::span<std::uint32_t> index_depth, std::span<std::uint32_t> index_id);

/// map_associate: pixel_match per pixel, and surfel_claim (capacity entries; reset to kUnclaimed
/// first) = lowest pixel index matched to each surfel.
void associateCpu(const MeasurementMaps& frame, std::span<const Surfel> surfels,
                  std::span<const std::uint32_t> index_id, const FusionParams& params,
                  std::span<std::uint32_t> pixel_match, std::span<std::uint32_t> surfel_claim);

/// map_fuse: fuses the claiming pixel into each claimed surfel of [0, surfel_count).
void fuseCpu(const MeasurementMaps& frame, const FusionParams& params, std::span<const std::uint32_t> surfel_claim,
             std::uint32_t surfel_count, std::span<Surfel> surfels);

/// map_insert, all passes: appends the kPixelNewSurfel pixels in pixel order behind
/// state.surfel_count, writing only below params.capacity (surfels holds at least that many), and
/// updates the state.
void insertCpu(const MeasurementMaps& frame, const FusionParams& params, std::span<const std::uint32_t> pixel_match,
               MapState& state, std::span<Surfel> surfels);

}  // namespace vifusion::map
