// Model prediction and map maintenance on the GPU against their CPU references (exact for splat
// ids, depth bits, keep flags, counts and compacted arrays; 1e-5 m for positions), and against the
// data: a map made from a real 7-Scenes frame, rendered back at that frame's pose, reproduces the
// frame's vertex map.

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <utility>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_maintenance.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/preprocess/cpu_reference.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

using map::Surfel;
using test::GpuTest;
using Vec4Image = Image<Eigen::Vector4f>;

constexpr std::uint32_t kFrame = 1000;  ///< frame number the synthetic maps live in (> every age used)

map::MapOptions mapOptions(std::uint32_t capacity) {
  map::MapOptions options;
  options.capacity = capacity;
  return options;
}

/// A map with prediction and maintenance on one arena, plus host staging buffers that write the map
/// and the index map and read every result back. Each step is its own sequence, recorded once.
class MapRig {
 public:
  MapRig(gpu::GpuContext& context, std::uint32_t capacity, const PinholeCamera& camera,
         const map::PredictionOptions& prediction_options = {}, const map::MapOptions* map_options = nullptr)
      : map_(plan_, map_options != nullptr ? *map_options : mapOptions(capacity), camera),
        prediction_(context, plan_, map_, camera, prediction_options),
        maintenance_(context, plan_, map_, camera) {
    const uint64_t surfel_bytes = uint64_t{capacity} * sizeof(Surfel);
    const uint64_t pixel_bytes = uint64_t(camera.width) * uint64_t(camera.height) * 4;
    surfel_upload_ = plan_.addBuffer("test.surfels", surfel_bytes, gpu::MemoryUse::Upload);
    keep_upload_ = plan_.addBuffer("test.keep", uint64_t{capacity} * 4, gpu::MemoryUse::Upload);
    index_depth_upload_ = plan_.addBuffer("test.index_depth", pixel_bytes, gpu::MemoryUse::Upload);
    index_id_upload_ = plan_.addBuffer("test.index_id", pixel_bytes, gpu::MemoryUse::Upload);
    compacted_ = readback(map_.surfels(1));
    keep_ = readback(maintenance_.keepFlags());
    depth_bits_ = readback(prediction_.splatDepthBits());
    ids_ = readback(prediction_.splatIds());
    for (int l = 0; l < prediction_.levels(); ++l) {
      const map::ModelLevelBuffers& level = prediction_.level(l);
      levels_.push_back({readback(level.vertices), readback(level.normals), readback(level.intensity)});
    }
    arena_ = gpu::MemoryArena::create(context, plan_);
    prediction_.build(*arena_);
    maintenance_.build(*arena_);
    map_.reset(*arena_);

    upload_ = sequence(context, "upload", [&](gpu::CommandRecorder& r) {
      r.copyBuffer(buffer(surfel_upload_), buffer(map_.surfels(0)), surfel_bytes);
      r.copyBuffer(buffer(index_depth_upload_), buffer(map_.indexDepth()), pixel_bytes);
      r.copyBuffer(buffer(index_id_upload_), buffer(map_.indexId()), pixel_bytes);
      r.computeBarrier();
    });
    predict_ = sequence(context, "predict", [&](gpu::CommandRecorder& r) {
      prediction_.record(r, 0);
      copyBack(r, {depth_bits_, ids_});
      for (const LevelMirrors& level : levels_) copyBack(r, {level.vertices, level.normals, level.intensity});
    });
    cleanup_ = sequence(context, "cleanup", [&](gpu::CommandRecorder& r) {
      maintenance_.recordCleanup(r, 0);
      copyBack(r, {keep_});
    });
    compact_flags_ = sequence(context, "compact", [&](gpu::CommandRecorder& r) {
      r.copyBuffer(buffer(keep_upload_), buffer(maintenance_.keepFlags()), buffer(keep_upload_).bytes);
      r.computeBarrier();
      maintenance_.recordCompaction(r, 0);
      copyBack(r, {compacted_});
    });
    maintain_ = sequence(context, "maintain", [&](gpu::CommandRecorder& r) {
      maintenance_.record(r, 0);
      copyBack(r, {compacted_, keep_});
    });
  }

  /// Writes `surfels` into array 0 and sets surfel_count.
  void writeMap(std::span<const Surfel> surfels) {
    std::memcpy(buffer(surfel_upload_).mapped, surfels.data(), surfels.size_bytes());
    map::MapState state;
    state.surfel_count = static_cast<std::uint32_t>(surfels.size());
    state.frame = kFrame;
    std::memcpy(buffer(map_.state()).mapped, &state, sizeof(state));
    upload_->run();
  }
  void writeIndexMap(ImageView<const std::uint32_t> depth_bits, ImageView<const std::uint32_t> ids) {
    std::memcpy(buffer(index_depth_upload_).mapped, depth_bits.data, depth_bits.pixelCount() * 4);
    std::memcpy(buffer(index_id_upload_).mapped, ids.data, ids.pixelCount() * 4);
  }
  std::span<std::uint32_t> keepUpload() { return buffer(keep_upload_).hostSpan<std::uint32_t>(); }

  void predict(const SE3d& T_C_W, std::uint32_t frame) {
    prediction_.setView(T_C_W, frame);
    predict_->run();
  }
  void cleanup(const SE3d& T_C_W) {
    maintenance_.setView(T_C_W, kFrame);
    cleanup_->run();
  }
  void compactUploadedFlags() { compact_flags_->run(); }
  void maintain(const SE3d& T_C_W) {
    maintenance_.setView(T_C_W, kFrame);
    maintain_->run();
  }

  template <typename T>
  ImageView<const T> image(gpu::BufferId readback_id, int level = 0) const {
    const PinholeCamera& camera = prediction_.camera(level);
    return {buffer(readback_id).hostSpan<const T>().data(), camera.width, camera.height};
  }
  struct LevelMirrors {
    gpu::BufferId vertices, normals, intensity;
  };
  const LevelMirrors& level(int l) const { return levels_[l]; }
  gpu::BufferId depthBits() const { return depth_bits_; }
  gpu::BufferId ids() const { return ids_; }
  std::span<const std::uint32_t> keep() const { return buffer(keep_).hostSpan<const std::uint32_t>(); }
  std::span<const Surfel> compacted() const { return buffer(compacted_).hostSpan<const Surfel>(); }
  std::uint32_t count() const { return map_.readState(*arena_).surfel_count; }
  const map::ModelPrediction& prediction() const { return prediction_; }
  const map::MapMaintenance& maintenance() const { return maintenance_; }

 private:
  gpu::BufferId readback(gpu::BufferId source) {
    const gpu::BufferRequest& request = plan_.buffers()[source.index];
    const gpu::BufferId id = plan_.addBuffer(request.name + ".readback", request.bytes, gpu::MemoryUse::Readback);
    mirrors_.push_back({source, id});
    return id;
  }
  void copyBack(gpu::CommandRecorder& r, std::initializer_list<gpu::BufferId> readbacks) {
    for (gpu::BufferId id : readbacks) {
      for (const auto& [source, target] : mirrors_) {
        if (target.index == id.index) r.copyBuffer(buffer(source), buffer(target), buffer(source).bytes);
      }
    }
    r.hostReadBarrier();
  }
  template <typename Fn>
  std::unique_ptr<gpu::CommandSequence> sequence(gpu::GpuContext& context, const char* name, Fn&& fn) {
    auto s = gpu::CommandSequence::create(context, name);
    s->record(fn);
    return s;
  }
  const gpu::GpuBuffer& buffer(gpu::BufferId id) const { return arena_->buffer(id); }

  gpu::CapacityPlan plan_;
  map::MapBuffers map_;
  map::ModelPrediction prediction_;
  map::MapMaintenance maintenance_;
  gpu::BufferId surfel_upload_, keep_upload_, index_depth_upload_, index_id_upload_;
  gpu::BufferId compacted_, keep_, depth_bits_, ids_;
  std::vector<LevelMirrors> levels_;
  std::vector<std::pair<gpu::BufferId, gpu::BufferId>> mirrors_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> upload_, predict_, cleanup_, compact_flags_, maintain_;
};

/// A real frame's camera-frame vertex and normal maps from bilateral-filtered depth. Filtered, not
/// raw: Kinect depth is quantised in steps of ≈ 1 cm at 2 m, and a splat renderer's depth test
/// picks the nearest of the overlapping disks, so raw steps would measure the sensor, not the
/// renderer.
struct FrameGeometry {
  Image<Eigen::Vector4f> vertices, normals;
};

FrameGeometry frameGeometry(const test::SevenScenesFrame& frame) {
  const PinholeCamera& camera = frame.camera;
  Image<float> depth(camera.width, camera.height), filtered(camera.width, camera.height);
  preprocess::DepthToMetricParams metric;
  metric.width = camera.width;
  metric.height = camera.height;
  preprocess::depthToMetricCpu(frame.depth_mm.view(), metric, depth.view());
  preprocess::BilateralDepthParams bilateral;
  bilateral.width = camera.width;
  bilateral.height = camera.height;
  preprocess::bilateralDepthCpu(depth.view(), bilateral, filtered.view());
  FrameGeometry g{Vec4Image(camera.width, camera.height, Eigen::Vector4f::Zero()),
                  Vec4Image(camera.width, camera.height, Eigen::Vector4f::Zero())};
  preprocess::vertexMapCpu(filtered.view(), preprocess::VertexMapParams::fromCamera(camera), g.vertices.view());
  preprocess::NormalMapParams normals;
  normals.width = camera.width;
  normals.height = camera.height;
  preprocess::normalMapCpu(g.vertices.view(), normals, g.normals.view());
  return g;
}

/// One surfel per pixel with a vertex and a normal, in W: radius √2·z/f (ElasticFusion's, without
/// its growth on slanted surfaces, which only widens the overlap the depth test resolves), colour
/// from the frame, created and updated at kFrame.
std::vector<Surfel> surfelsFromFrame(const test::SevenScenesFrame& frame, const FrameGeometry& g, float confidence) {
  std::vector<Surfel> surfels;
  const Eigen::Matrix3f R_W_C = frame.T_W_C.rotationMatrix().cast<float>();
  const Eigen::Vector3f t_W_C = frame.T_W_C.translation().cast<float>();
  for (int y = 0; y < frame.camera.height; ++y) {
    for (int x = 0; x < frame.camera.width; ++x) {
      const Eigen::Vector4f& v = g.vertices(x, y);
      const Eigen::Vector4f& n = g.normals(x, y);
      if (v.z() <= 0.0f || n.isZero(0.0f)) continue;
      Surfel s;
      const float z = v.z();
      const float radius = std::sqrt(2.0f) * z / static_cast<float>(frame.camera.fx);
      const Eigen::Vector3f p_C(v.x(), v.y(), v.z());
      const Eigen::Vector3f n_C(n.x(), n.y(), n.z());
      const Eigen::Vector3f p_W = R_W_C * p_C + t_W_C;
      const Eigen::Vector3f n_W = R_W_C * n_C;
      s.position_confidence = Eigen::Vector4f(p_W.x(), p_W.y(), p_W.z(), confidence);
      s.normal_radius = Eigen::Vector4f(n_W.x(), n_W.y(), n_W.z(), radius);
      const Rgb8 rgb = frame.rgb(x, y);
      s.setPackedColour(map::packRgb8(Eigen::Vector3f(rgb.r, rgb.g, rgb.b)));
      s.colour_times.y() = s.colour_times.z() = static_cast<float>(kFrame);
      surfels.push_back(s);
    }
  }
  return surfels;
}

/// `s` moved `toward_m` toward the camera at `camera_W` along its viewing ray.
Surfel movedToward(Surfel s, const Eigen::Vector3f& camera_W, float toward_m) {
  const Eigen::Vector3f p = s.position_confidence.head<3>();
  s.position_confidence.head<3>() = p + (camera_W - p).normalized() * toward_m;
  return s;
}

template <typename T>
std::size_t countDifferent(ImageView<const T> a, ImageView<const T> b) {
  std::size_t different = 0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) different += a(x, y) == b(x, y) ? 0 : 1;
  }
  return different;
}

double maxAbsDifference(ImageView<const Eigen::Vector4f> a, ImageView<const Eigen::Vector4f> b) {
  double worst = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) worst = std::max(worst, double((a(x, y) - b(x, y)).cwiseAbs().maxCoeff()));
  }
  return worst;
}

double maxAbsDifference(ImageView<const float> a, ImageView<const float> b) {
  double worst = 0.0;
  for (int y = 0; y < a.height; ++y) {
    for (int x = 0; x < a.width; ++x) worst = std::max(worst, double(std::abs(a(x, y) - b(x, y))));
  }
  return worst;
}

/// Expects the GPU prediction in `rig` to equal the CPU reference for `surfels` at every level.
void expectPredictionMatchesCpu(const MapRig& rig, std::span<const Surfel> surfels,
                                const map::PredictionParams& params) {
  const int w = params.view.width;
  const int h = params.view.height;
  Image<std::uint32_t> depth_bits(w, h), ids(w, h);
  map::splatModelCpu(surfels, params, depth_bits.view(), ids.view());
  EXPECT_EQ(countDifferent(rig.image<std::uint32_t>(rig.depthBits()), std::as_const(depth_bits).view()), 0u);
  EXPECT_EQ(countDifferent(rig.image<std::uint32_t>(rig.ids()), std::as_const(ids).view()), 0u);

  Vec4Image vertices0(w, h, Eigen::Vector4f::Zero()), normals0(w, h, Eigen::Vector4f::Zero());
  Image<float> intensity0(w, h);
  map::resolveModelCpu(surfels, params, ids.view(), vertices0.view(), normals0.view(), intensity0.view());
  for (int l = 0; l < rig.prediction().levels(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    const PinholeCamera& camera = rig.prediction().camera(l);
    Vec4Image vertices(camera.width, camera.height, Eigen::Vector4f::Zero());
    Vec4Image normals(camera.width, camera.height, Eigen::Vector4f::Zero());
    Image<float> intensity(camera.width, camera.height);
    map::subsampleModelCpu(vertices0.view(), normals0.view(), intensity0.view(), l, vertices.view(), normals.view(),
                           intensity.view());
    EXPECT_LE(maxAbsDifference(rig.image<Eigen::Vector4f>(rig.level(l).vertices, l), vertices.view()), 1e-5);
    EXPECT_LE(maxAbsDifference(rig.image<Eigen::Vector4f>(rig.level(l).normals, l), normals.view()), 1e-5);
    EXPECT_LE(maxAbsDifference(rig.image<float>(rig.level(l).intensity, l), intensity.view()), 1e-4);
  }
}

struct CameraCase {
  const char* name;
  double fy_sign;  ///< −1: ICL-NUIM-style negative fy
};
void PrintTo(const CameraCase& c, std::ostream* out) { *out << c.name; }

class MapPredictionTest : public GpuTest, public ::testing::WithParamInterface<CameraCase> {};

TEST_P(MapPredictionTest, RendersAFramesSurfelsBackIntoItsVertexMap) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  frame.camera.fy *= GetParam().fy_sign;
  const FrameGeometry geometry = frameGeometry(frame);
  std::vector<Surfel> surfels = surfelsFromFrame(frame, geometry, 20.0f);
  const std::size_t real = surfels.size();
  // Distractors 10 cm in front of every 10th surfel, which would win every depth test if rendered:
  // inactive (updated 300 frames ago) and unstable (confidence 1) ones.
  const Eigen::Vector3f camera_W = frame.T_W_C.translation().cast<float>();
  for (std::size_t i = 0; i < real; i += 10) {
    Surfel inactive = movedToward(surfels[i], camera_W, 0.10f);
    inactive.colour_times.z() = static_cast<float>(kFrame - 300);
    Surfel unstable = movedToward(surfels[i + 5 < real ? i + 5 : i], camera_W, 0.10f);
    unstable.position_confidence.w() = 1.0f;
    surfels.push_back(inactive);
    surfels.push_back(unstable);
  }

  MapRig rig(context(), 400'000, frame.camera);
  rig.writeMap(surfels);
  const SE3d T_C_W = frame.T_W_C.inverse();
  rig.predict(T_C_W, kFrame);
  expectPredictionMatchesCpu(rig, surfels, rig.prediction().makeParams(T_C_W, kFrame));

  // Against the data: where the frame has a surfel, the model must be there, at the same depth.
  const auto model = rig.image<Eigen::Vector4f>(rig.level(0).vertices);
  std::size_t with_surfel = 0, covered = 0, within_5mm = 0;
  std::vector<float> errors_m;
  for (int y = 0; y < frame.camera.height; ++y) {
    for (int x = 0; x < frame.camera.width; ++x) {
      if (geometry.vertices(x, y).z() <= 0.0f || geometry.normals(x, y).isZero(0.0f)) continue;
      ++with_surfel;
      if (model(x, y).z() <= 0.0f) continue;
      ++covered;
      const float error_m = (model(x, y) - geometry.vertices(x, y)).head<3>().norm();
      errors_m.push_back(error_m);
      within_5mm += error_m <= 0.005f ? 1 : 0;
    }
  }
  ASSERT_GT(with_surfel, 100'000u);
  std::nth_element(errors_m.begin(), errors_m.begin() + errors_m.size() / 2, errors_m.end());
  const double coverage = double(covered) / double(with_surfel);
  const double fraction_5mm = double(within_5mm) / double(covered);
  std::cout << "coverage " << coverage << ", within 5 mm " << fraction_5mm << ", median error "
            << errors_m[errors_m.size() / 2] * 1000.0f << " mm\n";
  EXPECT_GE(coverage, 0.9);
  // The rest lie at depth edges and on curved or rippled surfaces, where a neighbouring disk's
  // tangent plane passes in front of this pixel's own surfel and wins the depth test.
  EXPECT_GE(fraction_5mm, 0.95);
  EXPECT_LE(errors_m[errors_m.size() / 2], 0.001f);
}

TEST_P(MapPredictionTest, RendersUnstableSurfelsOnlyWhileTheMapIsYoung) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(175);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 1.0f);
  MapRig rig(context(), 400'000, frame.camera);
  const SE3d T_C_W = frame.T_W_C.inverse();
  const map::PredictionOptions defaults;
  for (std::uint32_t render_frame : {defaults.young_map_frames - 1, defaults.young_map_frames}) {
    SCOPED_TRACE("frame " + std::to_string(render_frame));
    for (Surfel& s : surfels) s.colour_times.y() = s.colour_times.z() = static_cast<float>(render_frame);
    rig.writeMap(surfels);
    rig.predict(T_C_W, render_frame);
    expectPredictionMatchesCpu(rig, surfels, rig.prediction().makeParams(T_C_W, render_frame));
    const auto ids = rig.image<std::uint32_t>(rig.ids());
    const auto covered = static_cast<std::size_t>(
        std::count_if(ids.data, ids.data + ids.pixelCount(), [](std::uint32_t id) { return id != map::kNoSurfel; }));
    if (render_frame < defaults.young_map_frames) {
      EXPECT_GE(covered, surfels.size() * 9 / 10);
    } else {
      EXPECT_EQ(covered, 0u);
    }
  }
}

std::size_t pixelCount(const PinholeCamera& camera) { return std::size_t(camera.width) * std::size_t(camera.height); }

/// Kinds of surfel by activity (updated within δ_t) and stability (confidence ≥ threshold).
enum class Activity { ActiveStable, ActiveUnstable, InactiveStable, InactiveUnstable };

Activity activityOf(const Surfel& s, const map::PredictionParams& params) {
  const bool active = map::framesSinceCpu(params.view, s.colour_times.z()) <= params.time_window_frames;
  const bool stable = s.position_confidence.w() >= params.confidence_threshold;
  return active ? (stable ? Activity::ActiveStable : Activity::ActiveUnstable)
                : (stable ? Activity::InactiveStable : Activity::InactiveUnstable);
}

/// Per kind, how many pixels of the splat id image its surfels won.
std::array<std::size_t, 4> pixelsWonByKind(ImageView<const std::uint32_t> ids, std::span<const Surfel> surfels,
                                           const map::PredictionParams& params) {
  std::array<std::size_t, 4> won{};
  for (int y = 0; y < ids.height; ++y) {
    for (int x = 0; x < ids.width; ++x) {
      if (ids(x, y) != map::kNoSurfel) ++won[static_cast<std::size_t>(activityOf(surfels[ids(x, y)], params))];
    }
  }
  return won;
}

// A map whose surfels take turns being active and stable, active and unstable, inactive and stable (last updated
// 300 frames ago), inactive and unstable, with the inactive ones 5 cm in front so that they would win every
// depth test they took part in: the active prediction shows only active stable surfels (as before), the inactive
// one only inactive stable ones, each exactly as its CPU reference.
TEST_P(MapPredictionTest, InactivePredictionRendersOnlyTheInactiveStableSurfels) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  const Eigen::Vector3f camera_W = frame.T_W_C.translation().cast<float>();
  constexpr std::uint32_t kInactiveAge = 300;  // > δ_t = 200
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    const auto kind = static_cast<Activity>(i % 4);
    if (kind == Activity::ActiveUnstable || kind == Activity::InactiveUnstable) {
      surfels[i].position_confidence.w() = 1.0f;
    }
    if (kind == Activity::InactiveStable || kind == Activity::InactiveUnstable) {
      surfels[i] = movedToward(surfels[i], camera_W, 0.05f);
      surfels[i].colour_times.z() = static_cast<float>(kFrame - kInactiveAge);
    }
  }
  const SE3d T_C_W = frame.T_W_C.inverse();
  for (const map::PredictedSurfels set : {map::PredictedSurfels::kActive, map::PredictedSurfels::kInactive}) {
    const bool inactive = set == map::PredictedSurfels::kInactive;
    SCOPED_TRACE(inactive ? "inactive" : "active");
    map::PredictionOptions options;
    options.surfels = set;
    MapRig rig(context(), 400'000, frame.camera, options);
    EXPECT_EQ(rig.prediction().surfels(), set);
    rig.writeMap(surfels);
    rig.predict(T_C_W, kFrame);
    const map::PredictionParams params = rig.prediction().makeParams(T_C_W, kFrame);
    EXPECT_EQ(params.surfels, static_cast<std::uint32_t>(set));
    expectPredictionMatchesCpu(rig, surfels, params);

    const std::array<std::size_t, 4> won = pixelsWonByKind(rig.image<std::uint32_t>(rig.ids()), surfels, params);
    const auto shown = static_cast<std::size_t>(inactive ? Activity::InactiveStable : Activity::ActiveStable);
    for (std::size_t kind = 0; kind < won.size(); ++kind) {
      SCOPED_TRACE("kind " + std::to_string(kind));
      if (kind == shown) {
        // A quarter of the frame's surfels, each disk √2 pixels wide: much of the image is covered.
        EXPECT_GE(won[kind], pixelCount(frame.camera) / 4);
      } else {
        EXPECT_EQ(won[kind], 0u);
      }
    }
  }
}

// The young-map rule (every active surfel before young_map_frames) is the active prediction's only: with a short
// time window that leaves inactive surfels in a young map, the inactive prediction still shows only stable ones.
TEST_P(MapPredictionTest, InactivePredictionIgnoresTheYoungMapRule) {
  test::SevenScenesFrame frame = test::loadSevenScenesFrame(175);
  frame.camera.fy *= GetParam().fy_sign;
  std::vector<Surfel> surfels = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  map::MapOptions map_options = mapOptions(400'000);
  map_options.time_window_frames = 5;
  const map::PredictionOptions defaults;
  const std::uint32_t render_frame = defaults.young_map_frames - 1;
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    if (i % 2 == 1) surfels[i].position_confidence.w() = 1.0f;  // unstable
    // Inactive at render_frame: 19 > 5 frames since the last update.
    surfels[i].colour_times.y() = surfels[i].colour_times.z() = 0.0f;
  }
  map::PredictionOptions options;
  options.surfels = map::PredictedSurfels::kInactive;
  MapRig rig(context(), 400'000, frame.camera, options, &map_options);
  rig.writeMap(surfels);
  const SE3d T_C_W = frame.T_W_C.inverse();
  rig.predict(T_C_W, render_frame);
  const map::PredictionParams params = rig.prediction().makeParams(T_C_W, render_frame);
  ASSERT_LT(params.view.frame, params.young_map_frames);
  expectPredictionMatchesCpu(rig, surfels, params);
  const std::array<std::size_t, 4> won = pixelsWonByKind(rig.image<std::uint32_t>(rig.ids()), surfels, params);
  EXPECT_GE(won[static_cast<std::size_t>(Activity::InactiveStable)], pixelCount(frame.camera) / 4);
  EXPECT_EQ(won[static_cast<std::size_t>(Activity::InactiveUnstable)], 0u);
  EXPECT_EQ(won[static_cast<std::size_t>(Activity::ActiveStable)], 0u);
  EXPECT_EQ(won[static_cast<std::size_t>(Activity::ActiveUnstable)], 0u);
}

TEST(PredictionOptions, ValidateNamesTheSurfelsField) {
  EXPECT_EQ(map::PredictionOptions{}.surfels, map::PredictedSurfels::kActive);
  map::PredictionOptions options;
  options.surfels = map::PredictedSurfels::kInactive;
  EXPECT_NO_THROW(options.validate());
  options.surfels = static_cast<map::PredictedSurfels>(2);
  test::expectError([&] { options.validate(); }, "prediction option 'surfels' must be kActive or kInactive");
}

INSTANTIATE_TEST_SUITE_P(Cameras, MapPredictionTest,
                         ::testing::Values(CameraCase{"kinect", 1.0}, CameraCase{"negative_fy", -1.0}),
                         [](const ::testing::TestParamInfo<CameraCase>& info) { return std::string(info.param.name); });

/// Surfel i sits at x = i, so any reordering or loss shows in the compacted array.
std::vector<Surfel> numberedSurfels(std::size_t count) {
  std::vector<Surfel> surfels(count);
  for (std::size_t i = 0; i < count; ++i) {
    surfels[i].position_confidence = Eigen::Vector4f(static_cast<float>(i), 1.0f, 2.0f, 3.0f);
    surfels[i].colour_times.w() = std::bit_cast<float>(static_cast<std::uint32_t>(i));  // exact beyond 2^24
  }
  return surfels;
}

bool sameSurfel(const Surfel& a, const Surfel& b) { return std::memcmp(&a, &b, sizeof(Surfel)) == 0; }

TEST_F(GpuTest, CompactionOfRandomFlagsAt2MSurfelsIsAStablePartition) {
  constexpr std::uint32_t kCapacity = 2'000'000;
  MapRig rig(context(), kCapacity, PinholeCamera::create(64, 48, 50, 50, 32, 24));
  EXPECT_EQ(rig.maintenance().scanLevels(), 3);  // 2 M flags → 1954 tile sums → 2 → total
  std::mt19937 random(7);
  // Full map, half kept; then a partial last tile with few survivors; then an empty map.
  for (const auto& [count, keep_probability] : {std::pair{kCapacity, 0.5}, {1'234'567u, 0.01}, {0u, 0.5}}) {
    SCOPED_TRACE("count " + std::to_string(count));
    const std::vector<Surfel> surfels = numberedSurfels(count);
    rig.writeMap(surfels);
    std::bernoulli_distribution keep(keep_probability);
    std::span<std::uint32_t> flags = rig.keepUpload();
    for (std::uint32_t i = 0; i < count; ++i) flags[i] = keep(random) ? 1u : 0u;
    rig.compactUploadedFlags();

    std::vector<Surfel> expected = surfels;
    const auto kept_end = std::stable_partition(expected.begin(), expected.end(), [&](const Surfel& s) {
      return flags[std::bit_cast<std::uint32_t>(s.colour_times.w())] != 0u;
    });
    const auto kept = static_cast<std::uint32_t>(kept_end - expected.begin());
    ASSERT_EQ(rig.count(), kept);
    EXPECT_EQ(rig.maintenance().stats().kept, kept);
    std::size_t mismatches = 0;
    for (std::uint32_t i = 0; i < kept; ++i) mismatches += sameSurfel(rig.compacted()[i], expected[i]) ? 0 : 1;
    EXPECT_EQ(mismatches, 0u);
  }
}

/// Level-0 index map as fusion's index kernel defines it: per pixel the nearest centre of an
/// active surfel (camera depth bits, index + 1). Exact ties go to the lower index (map_index picks
/// the higher; either serves the cleanup rules, which only read the neighbours' depth and state).
void nearestCentreIndexMap(std::span<const Surfel> surfels, const map::MapView& view, std::uint32_t time_window,
                           Image<std::uint32_t>& depth_bits, Image<std::uint32_t>& ids) {
  depth_bits.resize(view.width, view.height, 0xffffffffu);
  ids.resize(view.width, view.height, 0u);
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    if (map::framesSinceCpu(view, surfels[i].colour_times.z()) > time_window) continue;
    const Eigen::Vector3f p_C = map::transformPointCpu(view, surfels[i].position_confidence.head<3>());
    if (p_C.z() <= 0.0f) continue;
    const Eigen::Vector2f uv = map::projectPointCpu(view, p_C);
    const int x = static_cast<int>(std::floor(uv.x() + 0.5f));
    const int y = static_cast<int>(std::floor(uv.y() + 0.5f));
    if (!depth_bits.view().contains(x, y)) continue;
    const std::uint32_t bits = std::bit_cast<std::uint32_t>(p_C.z());
    if (bits < depth_bits(x, y)) {
      depth_bits(x, y) = bits;
      ids(x, y) = static_cast<std::uint32_t>(i + 1);
    }
  }
}

enum class Kind { Wall, Floater, OldUnstable, Inactive, InactiveUnstable, InactiveOld };

// Inactive surfels stay unless the map is full; then the never-stable ones go and, by the map-full
// policy's age (half the run on the first full frame: 500 of kFrame = 1000), the old stable ones.
TEST_F(GpuTest, CleanupMatchesItsCpuReferenceAndEvictsInactiveSurfelsOnlyWhenFull) {
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  const std::vector<Surfel> wall = surfelsFromFrame(frame, frameGeometry(frame), 20.0f);
  const Eigen::Vector3f camera_W = frame.T_W_C.translation().cast<float>();
  // Every 20th wall surfel gets one of five companions 20 cm in front of it.
  std::vector<Surfel> surfels = wall;
  std::vector<Kind> kinds(wall.size(), Kind::Wall);
  for (std::size_t i = 0; i < wall.size(); i += 20) {
    const auto kind = static_cast<Kind>(1 + (i / 20) % 5);
    Surfel s = movedToward(wall[i], camera_W, 0.20f);
    if (kind == Kind::Floater) s.colour_times.z() = static_cast<float>(kFrame - 5);
    if (kind == Kind::OldUnstable) {
      s.position_confidence.w() = 2.0f;
      s.colour_times.z() = static_cast<float>(kFrame - 30);
    }
    if (kind == Kind::Inactive || kind == Kind::InactiveUnstable) s.colour_times.z() = static_cast<float>(kFrame - 250);
    if (kind == Kind::InactiveUnstable) s.position_confidence.w() = 1.0f;
    if (kind == Kind::InactiveOld) s.colour_times.z() = static_cast<float>(kFrame - 600);
    surfels.push_back(s);
    kinds.push_back(kind);
  }
  const SE3d T_C_W = frame.T_W_C.inverse();

  // Roomy map first, then one over 95 % full, where inactive unstable and old surfels are evicted.
  for (const std::uint32_t capacity : {400'000u, static_cast<std::uint32_t>(surfels.size() * 1.02)}) {
    SCOPED_TRACE("capacity " + std::to_string(capacity));
    MapRig rig(context(), capacity, frame.camera);
    const map::MapView view = rig.maintenance().makeParams(T_C_W, kFrame).view;
    Image<std::uint32_t> index_depth, index_id;
    nearestCentreIndexMap(surfels, view, map::MapOptions{}.time_window_frames, index_depth, index_id);
    rig.writeIndexMap(index_depth.view(), index_id.view());
    rig.writeMap(surfels);
    rig.cleanup(T_C_W);  // the map-full policy's first frame at this count
    const map::CleanupParams params = rig.maintenance().makeParams(T_C_W, kFrame);
    const bool full = surfels.size() > params.full_count;
    EXPECT_EQ(params.eviction_age_frames, full ? kFrame / 2 : map::kNoAgeEviction);

    std::vector<std::uint32_t> keep(surfels.size());
    map::MaintenanceStats expected;
    map::cleanupCpu(surfels, params, index_depth.view(), index_id.view(), keep, expected);
    EXPECT_TRUE(std::equal(keep.begin(), keep.end(), rig.keep().begin()));
    EXPECT_EQ(rig.maintenance().stats(), expected);

    std::size_t removed[6] = {}, total[6] = {}, facing_floaters = 0;
    for (std::size_t i = 0; i < surfels.size(); ++i) {
      ++total[int(kinds[i])];
      removed[int(kinds[i])] += keep[i] == 0u ? 1 : 0;
      const Eigen::Vector3f n_C = map::rotateVectorCpu(params.view, surfels[i].normal_radius.head<3>());
      facing_floaters += kinds[i] == Kind::Floater && std::abs(n_C.z()) > params.facing_min_abs_nz ? 1 : 0;
    }
    EXPECT_EQ(removed[int(Kind::Inactive)], 0u);
    EXPECT_EQ(removed[int(Kind::InactiveUnstable)], full ? total[int(Kind::InactiveUnstable)] : 0u);
    EXPECT_EQ(removed[int(Kind::InactiveOld)], full ? total[int(Kind::InactiveOld)] : 0u);
    EXPECT_EQ(expected.evicted_when_full,
              full ? total[int(Kind::InactiveUnstable)] + total[int(Kind::InactiveOld)] : 0u);
    EXPECT_EQ(removed[int(Kind::OldUnstable)], total[int(Kind::OldUnstable)]);
    // Floaters are only tested when they face the camera; nearly all of those are seen through.
    EXPECT_LE(removed[int(Kind::Floater)], facing_floaters);
    EXPECT_GE(removed[int(Kind::Floater)], facing_floaters * 9 / 10);
    // Wall surfels go only at depth edges, where most of a 3×3 window lies on a farther surface.
    EXPECT_LE(removed[int(Kind::Wall)], total[int(Kind::Wall)] / 200);
    std::cout << "full " << full << ": removed floaters " << removed[int(Kind::Floater)] << " (facing "
              << facing_floaters << " of " << total[int(Kind::Floater)] << "), wall " << removed[int(Kind::Wall)] << "/"
              << total[int(Kind::Wall)] << "\n";

    // The whole maintenance step: cleanup then compaction into array 1. A second frame at this count:
    // a full map halves the eviction age (250 frames), which still spares Kind::Inactive (age 250).
    rig.maintain(T_C_W);
    const map::CleanupParams second = rig.maintenance().makeParams(T_C_W, kFrame);
    EXPECT_EQ(second.eviction_age_frames, full ? kFrame / 4 : map::kNoAgeEviction);
    map::MaintenanceStats second_stats;
    map::cleanupCpu(surfels, second, index_depth.view(), index_id.view(), keep, second_stats);
    EXPECT_EQ(second_stats, expected);
    std::vector<Surfel> compacted(surfels.size());
    const std::uint32_t kept = map::compactCpu(surfels, keep, compacted);
    ASSERT_EQ(rig.count(), kept);
    EXPECT_EQ(rig.maintenance().stats().kept, kept);
    std::size_t mismatches = 0;
    for (std::uint32_t i = 0; i < kept; ++i) mismatches += sameSurfel(rig.compacted()[i], compacted[i]) ? 0 : 1;
    EXPECT_EQ(mismatches, 0u);
  }
}

}  // namespace
}  // namespace vifusion
