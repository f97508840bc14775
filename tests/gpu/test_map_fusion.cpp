// Surfel fusion on the GPU (index map, association, fusion, insertion): every kernel against its CPU
// reference on real Kinect frames (7-Scenes), each fed the GPU's own input so a difference is that
// kernel's, also for a frame fused at an uncertain pose; noise reduction of fusion on a synthetic plane;
// the pose weight of an uncertain frame; a map that overflows; determinism.

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/map/fusion_cpu.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/surfel_fusion.hpp"
#include "vifusion/preprocess/packing.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

using map::MapState;
using map::Surfel;
using preprocess::NormalPixel;
using preprocess::VertexPixel;

/// A map with its fusion, fed either by the preprocessing stage (real frames) or by host-written
/// level-0 maps (synthetic scenes), with readback copies of everything the tests inspect.
class MapRig {
 public:
  MapRig(gpu::GpuContext& context, const PinholeCamera& camera, std::uint32_t capacity, bool use_preprocess,
         const map::FusionOptions& fusion_options = kinectNoiseFusion())
      : camera_(camera) {
    map::MapOptions options;
    options.capacity = capacity;
    map_ = std::make_unique<map::MapBuffers>(plan_, options, camera);
    const std::uint64_t pixels = std::uint64_t(camera.width) * std::uint64_t(camera.height);
    map::FusionInputs inputs;
    if (use_preprocess) {
      preprocess::PreprocessOptions preprocess_options;
      preprocess_options.camera = camera;
      stage_ = std::make_unique<preprocess::PreprocessStage>(context, plan_, preprocess_options);
      inputs = map::FusionInputs::fromPreprocess(*stage_);
      vertices_ = mirror(inputs.vertices);
      normals_ = mirror(inputs.normals);
    } else {
      inputs.vertices = vertices_ =
          plan_.addBuffer("test.vertices", pixels * sizeof(VertexPixel), gpu::MemoryUse::Upload);
      inputs.normals = normals_ = plan_.addBuffer("test.normals", pixels * sizeof(NormalPixel), gpu::MemoryUse::Upload);
      inputs.rgb_words = plan_.addBuffer("test.rgb", preprocess::packedRgbWordCount(camera.width, camera.height) * 4,
                                         gpu::MemoryUse::Upload);
    }
    rgb_words_ = inputs.rgb_words;
    fusion_ = std::make_unique<map::SurfelFusion>(context, plan_, *map_, camera, fusion_options);
    surfels_ = mirror(map_->surfels(0));
    other_surfels_ = mirror(map_->surfels(1));
    index_depth_ = mirror(map_->indexDepth());
    index_id_ = mirror(map_->indexId());
    pixel_match_ = mirror(fusion_->pixelMatch());
    surfel_claim_ = mirror(fusion_->surfelClaim());

    arena_ = gpu::MemoryArena::create(context, plan_);
    if (stage_) stage_->build(*arena_);
    fusion_->build(*arena_, inputs);
    map_->reset(*arena_);
    sequence_ = gpu::CommandSequence::create(context, "map fusion test");
    sequence_->record([&](gpu::CommandRecorder& recorder) {
      if (stage_) stage_->record(recorder);
      fusion_->record(recorder, 0);
      for (const auto& [source, readback] : mirrors_)
        recorder.copyBuffer(buffer(source), buffer(readback), buffer(source).bytes);
      recorder.hostReadBarrier();
    });
  }

  /// The fusion options of the tests: the defaults with the tracker's Kinect depth-noise model.
  static map::FusionOptions kinectNoiseFusion() {
    map::FusionOptions options;
    options.depth_noise = {0.0012f, 0.0019f, 0.4f};
    return options;
  }

  /// Fuses a real frame (through the preprocessing stage) as frame number `frame`.
  void run(const test::SevenScenesFrame& input, std::uint32_t frame, const map::FusionPoseUncertainty& uncertainty = {}) {
    stage_->upload(input.depth_mm.view(), input.rgb.view());
    run(input.T_W_C, frame, uncertainty);
  }
  /// Fuses the host-written maps (synthetic rigs) as frame number `frame`.
  void run(const SE3d& T_W_C, std::uint32_t frame, const map::FusionPoseUncertainty& uncertainty = {}) {
    fusion_->setFrame(T_W_C, frame, uncertainty);
    sequence_->run();
  }

  template <typename T>
  std::span<T> host(gpu::BufferId id) const {
    return buffer(id).hostSpan<T>();
  }

  std::span<VertexPixel> vertices() const { return host<VertexPixel>(vertices_); }
  std::span<NormalPixel> normals() const { return host<NormalPixel>(normals_); }
  std::span<std::uint32_t> rgbWords() const { return host<std::uint32_t>(rgb_words_); }
  std::span<const Surfel> surfels() const { return host<const Surfel>(surfels_); }
  std::span<const std::uint8_t> otherSurfelBytes() const { return host<const std::uint8_t>(other_surfels_); }
  std::span<const std::uint32_t> indexDepth() const { return host<const std::uint32_t>(index_depth_); }
  std::span<const std::uint32_t> indexId() const { return host<const std::uint32_t>(index_id_); }
  std::span<const std::uint32_t> pixelMatch() const { return host<const std::uint32_t>(pixel_match_); }
  std::span<const std::uint32_t> surfelClaim() const { return host<const std::uint32_t>(surfel_claim_); }
  MapState state() const { return map_->readState(*arena_); }
  const map::FusionParams& params() const { return fusion_->params(); }
  std::uint32_t capacity() const { return map_->capacity(); }

  map::MeasurementMaps maps() const {
    return {{vertices().data(), camera_.width, camera_.height},
            {normals().data(), camera_.width, camera_.height},
            rgbWords()};
  }
  /// Empties the map and fills the parity-1 array (unused here) with a pattern, as a guard.
  void reset(gpu::GpuContext& context, std::uint32_t guard_word) {
    map_->reset(*arena_);
    auto fill = gpu::CommandSequence::create(context, "guard fill");
    fill->record([&](gpu::CommandRecorder& recorder) {
      recorder.fillBuffer(buffer(map_->surfels(1)), guard_word);
      recorder.computeBarrier();
      recorder.copyBuffer(buffer(map_->surfels(1)), buffer(other_surfels_), buffer(other_surfels_).bytes);
      recorder.hostReadBarrier();
    });
    fill->run();
  }

  /// A sequence of fusion steps [first, last) only (timing).
  std::unique_ptr<gpu::CommandSequence> stepSequence(gpu::GpuContext& context, std::size_t first,
                                                     std::size_t last) const {
    auto sequence = gpu::CommandSequence::create(context, "fusion steps");
    sequence->record([&](gpu::CommandRecorder& recorder) {
      for (std::size_t s = first; s < last; ++s) fusion_->recordStep(recorder, map::kAllFusionSteps[s], 0);
    });
    return sequence;
  }

 private:
  gpu::BufferId mirror(gpu::BufferId source) {
    const gpu::BufferRequest& request = plan_.buffers()[source.index];
    const gpu::BufferId readback = plan_.addBuffer(request.name + ".readback", request.bytes, gpu::MemoryUse::Readback);
    mirrors_.push_back({source, readback});
    return readback;
  }
  const gpu::GpuBuffer& buffer(gpu::BufferId id) const { return arena_->buffer(id); }

  PinholeCamera camera_;
  gpu::CapacityPlan plan_;
  std::unique_ptr<preprocess::PreprocessStage> stage_;
  std::unique_ptr<map::MapBuffers> map_;
  std::unique_ptr<map::SurfelFusion> fusion_;
  std::vector<std::pair<gpu::BufferId, gpu::BufferId>> mirrors_;
  gpu::BufferId vertices_, normals_, rgb_words_, surfels_, other_surfels_, index_depth_, index_id_, pixel_match_,
      surfel_claim_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> sequence_;
};

/// The map as it was before a frame: the surfel array (capacity entries) and the state.
struct MapSnapshot {
  std::vector<Surfel> surfels;
  MapState state;
};
MapSnapshot snapshot(const MapRig& rig) { return {{rig.surfels().begin(), rig.surfels().end()}, rig.state()}; }

std::size_t countDifferent(std::span<const std::uint32_t> a, std::span<const std::uint32_t> b) {
  std::size_t n = 0;
  for (std::size_t i = 0; i < a.size(); ++i) n += a[i] != b[i] ? 1 : 0;
  return n;
}

/// Expects the GPU surfels [0, count) to equal the CPU's: positions within 1e-5 m, everything else
/// within float rounding (colour channels ±1 where an average rounds differently).
void expectSurfelsNear(std::span<const Surfel> gpu, std::span<const Surfel> cpu, std::uint32_t count) {
  double max_position = 0.0, max_normal = 0.0, max_radius = 0.0, max_confidence = 0.0;
  std::size_t time_mismatches = 0, colour_mismatches = 0;
  for (std::uint32_t i = 0; i < count; ++i) {
    const Surfel& g = gpu[i];
    const Surfel& c = cpu[i];
    max_position =
        std::max(max_position,
                 double((g.position_confidence.head<3>() - c.position_confidence.head<3>()).cwiseAbs().maxCoeff()));
    max_confidence = std::max(max_confidence, double(std::abs(g.position_confidence.w() - c.position_confidence.w())));
    max_normal =
        std::max(max_normal, double((g.normal_radius.head<3>() - c.normal_radius.head<3>()).cwiseAbs().maxCoeff()));
    max_radius = std::max(max_radius, double(std::abs(g.normal_radius.w() - c.normal_radius.w())));
    time_mismatches += g.colour_times.tail<3>() != c.colour_times.tail<3>() ? 1 : 0;
    const Eigen::Vector3f colour_diff = map::unpackRgb8(g.packedColour()) - map::unpackRgb8(c.packedColour());
    colour_mismatches += colour_diff.cwiseAbs().maxCoeff() > 1.0f ? 1 : 0;
  }
  EXPECT_LE(max_position, 1e-5);
  EXPECT_LE(max_normal, 1e-5);
  EXPECT_LE(max_radius, 1e-7);
  EXPECT_LE(max_confidence, 1e-5);
  EXPECT_EQ(time_mismatches, 0u);
  EXPECT_EQ(colour_mismatches, 0u);
  std::cout << "  surfels [0, " << count << "): max |Δposition| " << max_position << " m, |Δnormal| " << max_normal
            << ", |Δradius| " << max_radius << " m, |Δconfidence| " << max_confidence << "\n";
}

/// Checks every kernel of the frame just fused against its CPU reference, each on the GPU's input.
void expectFrameMatchesCpu(const MapRig& rig, const MapSnapshot& before) {
  const map::FusionParams& params = rig.params();
  const std::size_t pixels = rig.pixelMatch().size();
  std::vector<std::uint32_t> index_depth(pixels), index_id(pixels), pixel_match(pixels), claim(rig.capacity());

  map::indexMapCpu(before.surfels, before.state.surfel_count, params, index_depth, index_id);
  EXPECT_EQ(countDifferent(rig.indexDepth(), index_depth), 0u) << "index depth";
  EXPECT_EQ(countDifferent(rig.indexId(), index_id), 0u) << "index ids";

  map::associateCpu(rig.maps(), before.surfels, rig.indexId(), params, pixel_match, claim);
  EXPECT_EQ(countDifferent(rig.pixelMatch(), pixel_match), 0u) << "pixel matches";
  EXPECT_EQ(countDifferent(rig.surfelClaim(), claim), 0u) << "surfel claims";

  std::vector<Surfel> surfels = before.surfels;
  MapState state = before.state;
  map::fuseCpu(rig.maps(), params, rig.surfelClaim(), state.surfel_count, surfels);
  map::insertCpu(rig.maps(), params, rig.pixelMatch(), state, surfels);
  const MapState gpu_state = rig.state();
  EXPECT_EQ(gpu_state.surfel_count, state.surfel_count);
  EXPECT_EQ(gpu_state.overflow_count, state.overflow_count);
  EXPECT_EQ(gpu_state.frame, state.frame);
  expectSurfelsNear(rig.surfels(), surfels, std::min(gpu_state.surfel_count, state.surfel_count));

  const auto matched = std::count_if(pixel_match.begin(), pixel_match.end(), [](std::uint32_t m) {
    return m != map::kPixelNoMeasurement && m != map::kPixelNewSurfel;
  });
  const auto claimed = std::count_if(claim.begin(), claim.end(), [](std::uint32_t c) { return c != map::kUnclaimed; });
  const auto indexed = std::count_if(index_id.begin(), index_id.end(), [](std::uint32_t id) { return id != 0; });
  std::cout << "  frame " << params.frame << ": " << indexed << " index pixels, " << matched << " matched pixels, "
            << claimed << " fused surfels, " << state.surfel_count - before.state.surfel_count << " new surfels\n";
}

class MapFusionGpuTest : public test::GpuTest {};

TEST_F(MapFusionGpuTest, EveryKernelMatchesItsCpuReferenceOnRealFrames) {
  const test::SevenScenesFrame first = test::loadSevenScenesFrame(150);
  MapRig rig(context(), first.camera, 800'000, true);

  MapSnapshot before = snapshot(rig);
  rig.run(first, 1);
  SCOPED_TRACE("first frame, empty map");
  expectFrameMatchesCpu(rig, before);
  EXPECT_GT(rig.state().surfel_count, 200'000u) << "a real frame gives most of its pixels as surfels";

  // The last frame as if the IMU had carried its pose: its measurements are weighted down by the pose's
  // uncertainty (1 cm, 2 mrad), on the GPU as on the CPU.
  const map::FusionPoseUncertainty carried{1e-4, 4e-6};
  for (const auto& [index, frame] : {std::pair{155, 2u}, std::pair{160, 3u}}) {
    before = snapshot(rig);
    rig.run(test::loadSevenScenesFrame(index), frame, frame == 3u ? carried : map::FusionPoseUncertainty{});
    SCOPED_TRACE("frame " + std::to_string(index));
    expectFrameMatchesCpu(rig, before);
    const auto claimed = std::count_if(rig.surfelClaim().begin(), rig.surfelClaim().end(),
                                       [](std::uint32_t c) { return c != map::kUnclaimed; });
    EXPECT_GT(claimed, 100'000) << "a nearby pose must re-observe much of the map";
  }
}

/// A tilted plane seen by a 160 × 120 camera: camera-frame vertices with depth noise and the
/// true normal (facing the camera).
struct PlaneScene {
  PinholeCamera camera = PinholeCamera::create(160, 120, 160.0, 160.0, 79.5, 59.5);
  Eigen::Vector3d normal_C = Eigen::Vector3d(0.0, -0.3, -1.0).normalized();
  double offset_m = normal_C.dot(Eigen::Vector3d(0.0, 0.0, 1.5));  ///< plane: normal_C·x = offset_m
  SE3d T_W_C = SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Eigen::Vector3d(0.2, 1.0, 0.3).normalized())),
                    Eigen::Vector3d(0.5, -0.2, 1.0));

  void render(MapRig& rig, double sigma_m, std::mt19937& rng) const {
    std::normal_distribution<double> noise(0.0, sigma_m);
    for (int v = 0; v < camera.height; ++v) {
      for (int u = 0; u < camera.width; ++u) {
        const Eigen::Vector3d ray((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
        const double z_m = offset_m / normal_C.dot(ray) + noise(rng);
        const std::size_t i = std::size_t(v) * camera.width + u;
        rig.vertices()[i] << (ray * z_m).cast<float>(), 1.0f;
        rig.normals()[i] << normal_C.cast<float>(), 1.0f;
      }
    }
    std::fill(rig.rgbWords().begin(), rig.rgbWords().end(), 0x80808080u);
  }

  /// RMS distance of the map's surfels to the plane [m].
  double rmsDistance(const MapRig& rig) const {
    const SE3d T_C_W = T_W_C.inverse();
    double sum_sq = 0.0;
    const std::uint32_t count = rig.state().surfel_count;
    for (std::uint32_t i = 0; i < count; ++i) {
      const Eigen::Vector3d p_C = T_C_W * rig.surfels()[i].position_confidence.head<3>().cast<double>();
      sum_sq += std::pow(normal_C.dot(p_C) - offset_m, 2);
    }
    return std::sqrt(sum_sq / count);
  }
};

TEST_F(MapFusionGpuTest, FusingNoisyViewsOfAPlaneShrinksTheNoiseLikeOneOverRootN) {
  const PlaneScene scene;
  MapRig rig(context(), scene.camera, 50'000, false);
  std::mt19937 rng(42);
  const double sigma_m = 0.005;
  std::vector<double> rms;
  for (std::uint32_t frame = 1; frame <= 8; ++frame) {
    scene.render(rig, sigma_m, rng);
    rig.run(scene.T_W_C, frame);
    rms.push_back(scene.rmsDistance(rig));
    std::cout << "  after " << frame << " frames: " << rig.state().surfel_count << " surfels, rms to plane "
              << rms.back() * 1e3 << " mm (σ/√N·cos = " << sigma_m / std::sqrt(frame) * 1e3 << " mm ·cos)\n";
  }
  const std::uint32_t pixels = std::uint32_t(scene.camera.width * scene.camera.height);
  EXPECT_EQ(rig.state().surfel_count, pixels) << "every later view must fuse into the first view's surfels";
  EXPECT_GT(rms.front(), 0.004);
  EXPECT_LT(rms.back(), 0.0025);
  const double ratio = rms.back() / rms.front();
  EXPECT_NEAR(ratio, 1.0 / std::sqrt(8.0), 0.25 / std::sqrt(8.0));
}

// A view fused at an uncertain pose counts for less: each of its measurements gets the inverse-variance
// share σ_z²/(σ_z² + σ_r² + z²σ_θ²) of its radial confidence, and a registered view (no uncertainty) exactly 1.
TEST_F(MapFusionGpuTest, AViewFusedAtAnUncertainPoseIsWeightedByItsShareOfTheVariance) {
  const PlaneScene scene;
  const map::FusionOptions options = MapRig::kinectNoiseFusion();
  std::mt19937 rng(3);
  const map::FusionPoseUncertainty carried{0.004 * 0.004, 0.002 * 0.002};  // 4 mm, 2 mrad
  std::vector<float> confidence[2];
  for (const int uncertain : {0, 1}) {
    MapRig rig(context(), scene.camera, 50'000, false, options);
    scene.render(rig, 0.0, rng);
    rig.run(scene.T_W_C, 1, uncertain ? carried : map::FusionPoseUncertainty{});
    ASSERT_EQ(rig.state().surfel_count, std::uint32_t(scene.camera.width * scene.camera.height));
    for (std::uint32_t i = 0; i < rig.state().surfel_count; ++i) {
      confidence[uncertain].push_back(rig.surfels()[i].position_confidence.w());
    }
  }
  const SE3d T_C_W = scene.T_W_C.inverse();
  MapRig geometry(context(), scene.camera, 50'000, false, options);
  scene.render(geometry, 0.0, rng);
  geometry.run(scene.T_W_C, 1);
  double max_error = 0.0, min_weight = 1.0, max_weight = 0.0;
  for (std::size_t i = 0; i < confidence[0].size(); ++i) {
    const double z_m = (T_C_W * geometry.surfels()[i].position_confidence.head<3>().cast<double>()).z();
    const double dz = z_m - options.depth_noise.z0_m;
    const double sigma_z = options.depth_noise.a_m + options.depth_noise.b_per_m * dz * dz;
    const double weight = sigma_z * sigma_z /
                          (sigma_z * sigma_z + carried.position_variance_m2 + z_m * z_m * carried.rotation_variance_rad2);
    max_error = std::max(max_error, std::abs(confidence[1][i] / confidence[0][i] - weight));
    min_weight = std::min(min_weight, weight);
    max_weight = std::max(max_weight, weight);
  }
  std::cout << "  pose weight over the plane " << min_weight << " … " << max_weight << ", largest error " << max_error << "\n";
  EXPECT_LT(max_error, 1e-5);
  EXPECT_LT(max_weight, 0.9) << "4 mm and 2 mrad must matter at 1.2–2 m, where σ_z is 2–6 mm";
  EXPECT_GT(min_weight, 0.1);
}

TEST_F(MapFusionGpuTest, AFullMapCountsTheSurfelsItDropsAndNeverWritesPastTheEnd) {
  const PlaneScene scene;
  const std::uint32_t capacity = 5'000;
  MapRig rig(context(), scene.camera, capacity, false);
  const std::uint32_t guard = 0xA5A5A5A5u;
  rig.reset(context(), guard);
  std::mt19937 rng(7);
  const std::uint32_t pixels = std::uint32_t(scene.camera.width * scene.camera.height);
  std::uint32_t expected_overflow = 0;
  for (std::uint32_t frame = 1; frame <= 2; ++frame) {
    const MapSnapshot before = snapshot(rig);
    scene.render(rig, 0.001, rng);
    rig.run(scene.T_W_C, frame);
    SCOPED_TRACE("frame " + std::to_string(frame));
    expectFrameMatchesCpu(rig, before);
    const auto matched = std::count_if(rig.pixelMatch().begin(), rig.pixelMatch().end(),
                                       [](std::uint32_t m) { return m != map::kPixelNewSurfel; });
    expected_overflow += pixels - std::uint32_t(matched) - (capacity - before.state.surfel_count);
    EXPECT_EQ(rig.state().surfel_count, capacity);
    EXPECT_EQ(rig.state().overflow_count, expected_overflow);
  }
  EXPECT_GT(expected_overflow, pixels);
  // The other ping-pong array sits right behind the current one in the arena: a write past the
  // end would land there.
  const auto guard_bytes = rig.otherSurfelBytes();
  EXPECT_TRUE(std::all_of(guard_bytes.begin(), guard_bytes.end(), [](std::uint8_t b) { return b == 0xA5; }));
}

TEST_F(MapFusionGpuTest, TheSameFramesGiveByteIdenticalMaps) {
  const test::SevenScenesFrame a = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame b = test::loadSevenScenesFrame(155);
  MapRig rig(context(), a.camera, 800'000, true);
  std::vector<std::vector<Surfel>> runs;
  for (int run = 0; run < 2; ++run) {
    rig.reset(context(), 0u);
    rig.run(a, 1);
    rig.run(b, 2);
    const MapState state = rig.state();
    runs.emplace_back(rig.surfels().begin(), rig.surfels().begin() + state.surfel_count);
  }
  ASSERT_EQ(runs[0].size(), runs[1].size());
  ASSERT_GT(runs[0].size(), 0u);
  EXPECT_EQ(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(Surfel)), 0);
}

}  // namespace
}  // namespace vifusion
