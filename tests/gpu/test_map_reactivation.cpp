// Reactivation of the inactive surfels in view (map_reactivate.comp, map_reactivate_move.comp) against their CPU
// references, bit for bit, and from first principles: every surfel on the inactive prediction's surface within the
// fusion association's gates comes back — the hidden ones behind each pixel's winner included — and none behind
// the surface or at another angle; the list's capacity defers the excess to the next reactivation; the reactivated
// surfels leave the inactive prefix with nothing lost.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <set>
#include <span>
#include <string>
#include <vector>

#include "block_wall.hpp"
#include "gpu_test_environment.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/map/surfel_reactivation.hpp"

namespace vifusion {
namespace {

using map::Surfel;

const PinholeCamera& kCamera = test::kBlockWallCamera;
constexpr float kWallDepth_m = test::kBlockWallDepth_m;
constexpr std::uint32_t kFrame = test::kBlockWallFrame;  ///< the frame the map is predicted and reactivated in
constexpr std::uint32_t kWindowFrames = 200;             ///< MapOptions' δ_t
constexpr float kStableConfidence = test::kBlockWallStableConfidence;
constexpr std::size_t kWallSurfels = 60 * 60;

bool isInactiveStable(const Surfel& s) {
  return s.position_confidence.w() >= kStableConfidence && kFrame - s.colour_times.z() > kWindowFrames;
}

/// Behind each inactive stable wall surfel, copies moved `depth_m` further along its pixel ray (a third of a pixel
/// aside, so its centre stays in the same pixel) and, with `tilt_rad`, their normals tilted about x.
std::vector<Surfel> twinsBehind(std::span<const Surfel> wall, float depth_m, float tilt_rad) {
  std::vector<Surfel> twins;
  for (const Surfel& s : wall) {
    if (!isInactiveStable(s)) continue;
    Surfel twin = s;
    const float scale = (kWallDepth_m + depth_m) / kWallDepth_m;
    twin.position_confidence.head<3>() *= scale;
    twin.position_confidence.x() += kWallDepth_m / 180.0f;
    twin.normal_radius.head<3>() << 0.0f, std::sin(tilt_rad), -std::cos(tilt_rad);
    twins.push_back(twin);
  }
  return twins;
}

/// A map with its inactive prediction and reactivation, plus an active prediction, uploads into either surfel
/// array, and readbacks of the inactive prediction's level-0 vertices and normals and both predictions' splat ids.
class ReactivationRig {
 public:
  ReactivationRig(gpu::GpuContext& context, std::uint32_t capacity)
      : map_(plan_, mapOptions(capacity), kCamera),
        active_(context, plan_, map_, kCamera, predictionOptions(map::PredictedSurfels::kActive)),
        inactive_(context, plan_, map_, kCamera, predictionOptions(map::PredictedSurfels::kInactive)),
        reactivation_(context, plan_, map_, inactive_, map::FusionOptions{}),
        export_(context, plan_, map_) {
    const std::uint64_t surfel_bytes = std::uint64_t{capacity} * sizeof(Surfel);
    const std::uint64_t pixels = std::uint64_t(kCamera.width) * std::uint64_t(kCamera.height);
    upload_ = plan_.addBuffer("test.surfels", surfel_bytes, gpu::MemoryUse::Upload);
    vertices_ = plan_.addBuffer("test.vertices", pixels * sizeof(Eigen::Vector4f), gpu::MemoryUse::Readback);
    normals_ = plan_.addBuffer("test.normals", pixels * sizeof(Eigen::Vector4f), gpu::MemoryUse::Readback);
    active_ids_ = plan_.addBuffer("test.active_ids", pixels * sizeof(std::uint32_t), gpu::MemoryUse::Readback);
    inactive_ids_ = plan_.addBuffer("test.inactive_ids", pixels * sizeof(std::uint32_t), gpu::MemoryUse::Readback);
    arena_ = gpu::MemoryArena::create(context, plan_);
    active_.build(*arena_);
    inactive_.build(*arena_);
    reactivation_.build(*arena_);
    export_.build(*arena_);
    map_.reset(*arena_);
    // setMap writes both arrays and makes array 0 current; the predictions render it.
    upload_both_ = gpu::CommandSequence::create(context, "upload");
    upload_both_->record([&](gpu::CommandRecorder& r) {
      for (int parity = 0; parity < 2; ++parity) {
        r.copyBuffer(buffer(upload_), buffer(map_.surfels(parity)), surfel_bytes);
      }
      r.computeBarrier();
    });
    predict_ = gpu::CommandSequence::create(context, "predict");
    predict_->record([&](gpu::CommandRecorder& r) {
      active_.record(r, 0);
      inactive_.record(r, 0);
      r.copyBuffer(buffer(inactive_.level(0).vertices), buffer(vertices_), pixels * sizeof(Eigen::Vector4f));
      r.copyBuffer(buffer(inactive_.level(0).normals), buffer(normals_), pixels * sizeof(Eigen::Vector4f));
      r.copyBuffer(buffer(active_.splatIds()), buffer(active_ids_), pixels * sizeof(std::uint32_t));
      r.copyBuffer(buffer(inactive_.splatIds()), buffer(inactive_ids_), pixels * sizeof(std::uint32_t));
      r.hostReadBarrier();
    });
  }

  /// Writes `surfels` into both arrays and makes the first current, with [0, active_begin) the inactive prefix.
  void setMap(std::span<const Surfel> surfels, std::uint32_t active_begin = 0) {
    std::memcpy(buffer(upload_).mapped, surfels.data(), surfels.size_bytes());
    upload_both_->run();
    if (map_.current() != 0) map_.flip();
    map::MapState state;
    state.surfel_count = static_cast<std::uint32_t>(surfels.size());
    state.frame = kFrame;
    state.active_begin = active_begin;
    std::memcpy(buffer(map_.state()).mapped, &state, sizeof(state));
  }
  /// Both predictions of array 0 (setMap makes it current), camera at the origin of W looking along +z.
  void predict() {
    active_.setView(SE3d(), kFrame);
    inactive_.setView(SE3d(), kFrame);
    predict_->run();
  }
  map::PredictionParams inactiveParams() const { return inactive_.makeParams(SE3d(), kFrame); }
  ImageView<const Eigen::Vector4f> vertices() const { return image<Eigen::Vector4f>(vertices_); }
  ImageView<const Eigen::Vector4f> normals() const { return image<Eigen::Vector4f>(normals_); }
  ImageView<const std::uint32_t> activeIds() const { return image<std::uint32_t>(active_ids_); }
  ImageView<const std::uint32_t> inactiveIds() const { return image<std::uint32_t>(inactive_ids_); }
  map::SurfelReactivation& reactivation() { return reactivation_; }
  map::MapState mapState() const { return map_.readState(*arena_); }
  std::vector<Surfel> surfels() {
    std::vector<Surfel> out;
    export_.read(out);
    return out;
  }
  /// The live surfels of the other array (the export reads the current one).
  std::vector<Surfel> otherSurfels() {
    map_.flip();
    std::vector<Surfel> out = surfels();
    map_.flip();
    return out;
  }

 private:
  static map::MapOptions mapOptions(std::uint32_t capacity) {
    map::MapOptions options;
    options.capacity = capacity;
    options.time_window_frames = kWindowFrames;
    return options;
  }
  static map::PredictionOptions predictionOptions(map::PredictedSurfels surfels) {
    map::PredictionOptions options;
    options.surfels = surfels;
    return options;
  }
  template <typename T>
  ImageView<const T> image(gpu::BufferId id) const {
    return {buffer(id).hostSpan<const T>().data(), kCamera.width, kCamera.height};
  }
  const gpu::GpuBuffer& buffer(gpu::BufferId id) const { return arena_->buffer(id); }

  gpu::CapacityPlan plan_;
  map::MapBuffers map_;
  map::ModelPrediction active_;
  map::ModelPrediction inactive_;
  map::SurfelReactivation reactivation_;
  map::MapExport export_;
  gpu::BufferId upload_, vertices_, normals_, active_ids_, inactive_ids_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> upload_both_, predict_;
};

/// The CPU reference's marks on `surfels` for the rig's last prediction, with the rig's gates.
std::vector<std::uint32_t> referenceMarks(const ReactivationRig& rig, std::vector<Surfel>& surfels) {
  const map::ReactivateGates gates =
      map::ReactivateGates::of(map::FusionOptions{}, map::kReactivatedPerPixel * kCamera.width * kCamera.height);
  return map::reactivateInViewCpu(surfels, rig.inactiveParams(), rig.vertices(), rig.normals(), gates);
}

class MapReactivationTest : public test::GpuTest {};

// The wall's inactive stable surfels, each with a hidden twin 1 cm behind it (within the 5 cm association gate),
// one 30 cm behind (beyond it) and one 1 cm behind at 0.6 rad (beyond the 0.5 rad normal gate): the wall and its
// near twins come back, the others stay inactive. GPU against reactivateInViewCpu, bit for bit; the active
// prediction then renders them and the inactive one is empty.
TEST_F(MapReactivationTest, EverySurfelOnTheInactiveSurfaceComesBackAndNoneBehindIt) {
  const std::vector<Surfel> wall = test::blockWallSurfels();
  std::vector<Surfel> map = wall;
  const std::vector<Surfel> near = twinsBehind(wall, 0.01f, 0.0f);
  const std::vector<Surfel> far = twinsBehind(wall, 0.30f, 0.0f);
  const std::vector<Surfel> tilted = twinsBehind(wall, 0.01f, 0.6f);
  for (const auto* twins : {&near, &far, &tilted}) map.insert(map.end(), twins->begin(), twins->end());
  ReactivationRig rig(context(), static_cast<std::uint32_t>(map.size()));
  rig.setMap(map);
  rig.predict();
  std::vector<Surfel> expected = map;
  const std::vector<std::uint32_t> marked = referenceMarks(rig, expected);

  const std::size_t inactive_wall = near.size();
  ASSERT_GT(inactive_wall, 500u) << "the inactive stable blocks are in view";
  std::set<std::uint32_t> expected_marks;
  for (std::size_t i = 0; i < map.size(); ++i) {
    const bool wall_or_near_twin = i < kWallSurfels ? isInactiveStable(map[i]) : i < kWallSurfels + inactive_wall;
    if (wall_or_near_twin) expected_marks.insert(static_cast<std::uint32_t>(i));
  }
  EXPECT_EQ(std::set<std::uint32_t>(marked.begin(), marked.end()), expected_marks) << "the reference's own marks";

  rig.reactivation().apply();
  EXPECT_EQ(rig.reactivation().lastFound(), marked.size());
  const std::vector<Surfel> gpu = rig.surfels();
  ASSERT_EQ(gpu.size(), expected.size());
  EXPECT_EQ(0, std::memcmp(gpu.data(), expected.data(), gpu.size() * sizeof(Surfel)));

  rig.setMap(gpu);
  rig.predict();
  int inactive_pixels = 0, reactivated_pixels = 0;
  for (int y = 0; y < kCamera.height; ++y) {
    for (int x = 0; x < kCamera.width; ++x) {
      const std::uint32_t inactive_id = rig.inactiveIds()(x, y);
      if (inactive_id != map::kNoSurfel) {
        ++inactive_pixels;
        EXPECT_EQ(expected_marks.count(inactive_id), 0u) << "a reactivated surfel still inactive at " << x << ", " << y;
      }
      const std::uint32_t id = rig.activeIds()(x, y);
      if (id != map::kNoSurfel && expected_marks.count(id) > 0) ++reactivated_pixels;
    }
  }
  EXPECT_GT(inactive_pixels, 500) << "the tilted and far twins are still inactive";
  EXPECT_GT(reactivated_pixels, 500);
}

// More surfels on the surface than the list holds (kReactivatedPerPixel per pixel): the first reactivation marks
// exactly its capacity and reports how many it found; the next, on a fresh prediction, takes the rest.
TEST_F(MapReactivationTest, SurfelsPastTheCapacityComeBackAtTheNextReactivation) {
  const std::vector<Surfel> wall = test::blockWallSurfels();
  std::vector<Surfel> map = wall;
  constexpr int kLayers = 12;  // 13 layers of ~900 inactive surfels within 4 cm: past 2 × 4800
  for (int layer = 1; layer <= kLayers; ++layer) {
    const std::vector<Surfel> twins = twinsBehind(wall, 0.003f * static_cast<float>(layer), 0.0f);
    map.insert(map.end(), twins.begin(), twins.end());
  }
  const auto on_surface = static_cast<std::uint32_t>(std::count_if(map.begin(), map.end(), isInactiveStable));
  ReactivationRig rig(context(), static_cast<std::uint32_t>(map.size()));
  const std::uint32_t capacity = rig.reactivation().capacity();
  ASSERT_GT(on_surface, capacity);
  rig.setMap(map);
  rig.predict();
  rig.reactivation().apply();
  EXPECT_EQ(rig.reactivation().lastFound(), on_surface);
  std::vector<Surfel> after = rig.surfels();
  const auto still_inactive = static_cast<std::uint32_t>(std::count_if(after.begin(), after.end(), isInactiveStable));
  EXPECT_EQ(still_inactive, on_surface - capacity);

  rig.setMap(after);
  rig.predict();
  rig.reactivation().apply();
  EXPECT_EQ(rig.reactivation().lastFound(), on_surface - capacity);
  after = rig.surfels();
  EXPECT_EQ(std::count_if(after.begin(), after.end(), isInactiveStable), 0);
}

// In a map whose inactive surfels form the prefix (as after maintenance), the reactivated ones move into the
// active range and the prefix shrinks by their number, so the next frame visits them without visiting the whole
// map. GPU against the CPU references (mark, plan, move), bit for bit, in both arrays; and from first principles:
// nothing lost or duplicated, every reactivated surfel above the new prefix's end, and the prefix the same in both
// arrays.
TEST_F(MapReactivationTest, ReactivatedSurfelsLeaveTheInactivePrefix) {
  const std::vector<Surfel> wall = test::blockWallSurfels();
  std::vector<Surfel> with_twins = wall;
  const std::vector<Surfel> near = twinsBehind(wall, 0.01f, 0.0f);
  with_twins.insert(with_twins.end(), near.begin(), near.end());
  std::vector<Surfel> map_order;  // inactive first: the prefix
  for (const bool inactive : {true, false}) {
    for (const Surfel& s : with_twins) {
      if ((kFrame - s.colour_times.z() > kWindowFrames) == inactive) map_order.push_back(s);
    }
  }
  const auto count = static_cast<std::uint32_t>(map_order.size());
  const auto prefix =
      static_cast<std::uint32_t>(std::count_if(with_twins.begin(), with_twins.end(), [](const Surfel& s) {
        return kFrame - s.colour_times.z() > kWindowFrames;
      }));
  ReactivationRig rig(context(), count);
  rig.setMap(map_order, prefix);
  rig.predict();

  std::vector<Surfel> expected = map_order;
  const std::vector<std::uint32_t> marked = referenceMarks(rig, expected);
  std::vector<std::uint32_t> scratch(marked.size());
  std::vector<map::ReactivationMove> moves(marked.size());
  const map::ReactivationPlan plan = map::planReactivationMoves(marked, prefix, scratch, moves);
  std::vector<Surfel> expected_other = map_order;
  map::applyReactivationMovesCpu(expected, expected_other, std::span(moves.data(), plan.moves));
  ASSERT_GT(prefix - plan.active_begin, 1000u) << "the inactive blocks and their twins are in view";
  ASSERT_GT(plan.moves, 0u) << "some reactivated surfels sit below the new prefix end";

  EXPECT_EQ(rig.reactivation().apply(), prefix - plan.active_begin);
  EXPECT_EQ(rig.mapState().active_begin, plan.active_begin);
  EXPECT_EQ(rig.mapState().surfel_count, count);
  const std::vector<Surfel> gpu = rig.surfels();
  const std::vector<Surfel> other = rig.otherSurfels();
  ASSERT_EQ(gpu.size(), expected.size());
  EXPECT_EQ(0, std::memcmp(gpu.data(), expected.data(), gpu.size() * sizeof(Surfel)));
  EXPECT_EQ(0, std::memcmp(other.data(), expected.data(), plan.active_begin * sizeof(Surfel))) << "prefix in both";

  // First principles, on the GPU's result.
  const auto less = [](const Surfel& a, const Surfel& b) { return std::memcmp(&a, &b, sizeof(Surfel)) < 0; };
  std::vector<Surfel> before = map_order;
  std::vector<Surfel> after = gpu;
  for (Surfel& s : before) s.colour_times.z() = 0.0f;  // the mark is the one change allowed
  for (Surfel& s : after) s.colour_times.z() = 0.0f;
  std::sort(before.begin(), before.end(), less);
  std::sort(after.begin(), after.end(), less);
  EXPECT_EQ(0, std::memcmp(before.data(), after.data(), before.size() * sizeof(Surfel))) << "nothing lost";
  std::uint32_t reactivated_above = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const bool reactivated = gpu[i].colour_times.z() == static_cast<float>(kFrame);  // active ones: kFrame − 3
    if (i < plan.active_begin) {
      EXPECT_FALSE(reactivated) << "slot " << i << " left in the prefix";
    }
    reactivated_above += reactivated ? 1 : 0;
  }
  EXPECT_EQ(reactivated_above, prefix - plan.active_begin) << "every reactivated surfel in the active range";
}

}  // namespace
}  // namespace vifusion
