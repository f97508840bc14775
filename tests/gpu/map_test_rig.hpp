#pragma once
// The map test rig shared by the prediction and maintenance GPU tests: a map with prediction and maintenance
// on one arena, host staging to write maps and read every result back, and helpers that build surfel maps from
// a real 7-Scenes frame and compare images. Test-only; included by one test file each, so the helpers live in
// an anonymous namespace.

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
    retire_upload_ = plan_.addBuffer("test.retire", uint64_t{capacity} * 4, gpu::MemoryUse::Upload);
    index_depth_upload_ = plan_.addBuffer("test.index_depth", pixel_bytes, gpu::MemoryUse::Upload);
    index_id_upload_ = plan_.addBuffer("test.index_id", pixel_bytes, gpu::MemoryUse::Upload);
    compacted_ = readback(map_.surfels(1));
    previous_ = readback(map_.surfels(0));
    keep_ = readback(maintenance_.keepFlags());
    retire_ = readback(maintenance_.retireFlags());
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
      // Both arrays: they share the inactive prefix (map_buffers.hpp).
      r.copyBuffer(buffer(surfel_upload_), buffer(map_.surfels(0)), surfel_bytes);
      r.copyBuffer(buffer(surfel_upload_), buffer(map_.surfels(1)), surfel_bytes);
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
      copyBack(r, {keep_, retire_});
    });
    compact_flags_ = sequence(context, "compact", [&](gpu::CommandRecorder& r) {
      r.copyBuffer(buffer(keep_upload_), buffer(maintenance_.keepFlags()), buffer(keep_upload_).bytes);
      r.copyBuffer(buffer(retire_upload_), buffer(maintenance_.retireFlags()), buffer(retire_upload_).bytes);
      r.computeBarrier();
      maintenance_.recordCompaction(r, 0);
      copyBack(r, {compacted_, previous_});
    });
    maintain_ = sequence(context, "maintain", [&](gpu::CommandRecorder& r) {
      maintenance_.record(r, 0);
      copyBack(r, {compacted_, previous_, keep_, retire_});
    });
  }

  /// Writes `surfels` into both arrays and sets surfel_count and active_begin (the inactive prefix's end).
  void writeMap(std::span<const Surfel> surfels, std::uint32_t active_begin = 0) {
    std::memcpy(buffer(surfel_upload_).mapped, surfels.data(), surfels.size_bytes());
    map::MapState state;
    state.surfel_count = static_cast<std::uint32_t>(surfels.size());
    state.active_begin = active_begin;
    state.frame = kFrame;
    std::memcpy(buffer(map_.state()).mapped, &state, sizeof(state));
    upload_->run();
  }
  void writeIndexMap(ImageView<const std::uint32_t> depth_bits, ImageView<const std::uint32_t> ids) {
    std::memcpy(buffer(index_depth_upload_).mapped, depth_bits.data, depth_bits.pixelCount() * 4);
    std::memcpy(buffer(index_id_upload_).mapped, ids.data, ids.pixelCount() * 4);
  }
  std::span<std::uint32_t> keepUpload() { return buffer(keep_upload_).hostSpan<std::uint32_t>(); }
  std::span<std::uint32_t> retireUpload() { return buffer(retire_upload_).hostSpan<std::uint32_t>(); }

  void predict(const SE3d& T_C_W, std::uint32_t frame) {
    prediction_.setView(T_C_W, frame);
    predict_->run();
  }
  /// The prediction with the view the caller set (prediction().setView).
  void runPrediction() { predict_->run(); }
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
  std::span<const std::uint32_t> retire() const { return buffer(retire_).hostSpan<const std::uint32_t>(); }
  /// Array 1 after a compaction of array 0, and array 0 itself (whose prefix the compaction extends).
  std::span<const Surfel> compacted() const { return buffer(compacted_).hostSpan<const Surfel>(); }
  std::span<const Surfel> previous() const { return buffer(previous_).hostSpan<const Surfel>(); }
  std::uint32_t count() const { return map_.readState(*arena_).surfel_count; }
  map::MapExtent extent() const {
    const map::MapState state = map_.readState(*arena_);
    return {state.active_begin, state.surfel_count};
  }
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
  gpu::BufferId surfel_upload_, keep_upload_, retire_upload_, index_depth_upload_, index_id_upload_;
  gpu::BufferId compacted_, previous_, keep_, retire_, depth_bits_, ids_;
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

}  // namespace
}  // namespace vifusion
