// Loop closure's CPU stages at 640×480 (issue 16): the fern place recognition (encoding a frame, querying a
// database of keyframes from a walk round the synthetic living room) and the deformation graph's solve
// (node count × one closure's constraints: ElasticFusion's 32 × 24 grid, an E_con and an E_pin per point).
// The GPU stages (rendering the inactive model, registration, moving the map) are timed per closure by
// `vifusion run` (report.json: closures.stages_ms). Goal: a whole closure within one frame period at 30 Hz on
// a real GPU and within 0.5 s on lavapipe. Numbers: README.md here.
// JSON: bench_loop_closure --benchmark_out=bench.json --benchmark_out_format=json

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdint>
#include <numbers>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/core/pinhole_camera.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/loop/fern_database.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/scene/look_at.hpp"
#include "vifusion/scene/renderer.hpp"
#include "vifusion/scene/row_pool.hpp"

namespace vifusion::loop {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 480;
constexpr double kDepthScale_m = 1.0 / 5000.0;  // TUM / ICL-NUIM depth units

/// Views along a circle round the living room, looking outwards at the walls and furniture: consecutive views
/// overlap, views half a circle apart do not, as on a walk that maps the room. Rendered once (point-sampled
/// colour: the ferns average 8 × 8 blocks, antialiasing would not change their codes).
const std::vector<RgbdFrame>& walkFrames(int count) {
  static std::vector<RgbdFrame> frames;
  if (static_cast<int>(frames.size()) >= count) return frames;
  static const scene::LivingRoom room;
  static scene::RowPool pool;
  scene::RenderOptions options;
  options.filter_textures = false;
  options.edge_samples_per_axis = 1;
  options.depth_scale = 1.0 / kDepthScale_m;
  const scene::Renderer renderer(room, pool, options);
  const PinholeCamera camera = PinholeCamera::create(kWidth, kHeight, 481.2, -480.0, 319.5, 239.5);
  frames.clear();
  for (int i = 0; i < count; ++i) {
    const double azimuth = 2.0 * std::numbers::pi * i / count;
    const Eigen::Vector3d eye(0.3 * std::cos(azimuth), 1.3, -1.5 + 0.3 * std::sin(azimuth));
    const Eigen::Vector3d target = eye + Eigen::Vector3d(std::cos(azimuth), -0.2, std::sin(azimuth));
    RgbdFrame frame;
    frame.index = i;
    frame.depth_scale_m = kDepthScale_m;
    frame.rgb.resize(kWidth, kHeight);
    frame.depth.resize(kWidth, kHeight);
    renderer.render(scene::lookAt(eye, target), camera, frame.rgb.view(), frame.depth.view());
    frames.push_back(std::move(frame));
  }
  return frames;
}

void fernEncode(benchmark::State& state) {
  FernDatabase database(FernOptions{}, kWidth, kHeight);
  FernFrame encoded = database.makeFrame();
  const RgbdFrame& frame = walkFrames(1).front();
  for (auto _ : state) {
    database.encode(frame, encoded);
    benchmark::DoNotOptimize(encoded.codes.validCount());
  }
}

/// Argument: frames of the walk, every one stored as a keyframe (threshold 0: a query's cost grows with the
/// keyframes that share its codes, and a walk round one room stores only a few dozen at the default threshold).
/// Each query is a frame of the walk against all keyframes, as relocalisation does (min_frame_gap 0).
void fernQuery(benchmark::State& state) {
  const int offered = static_cast<int>(state.range(0));
  const std::vector<RgbdFrame>& frames = walkFrames(offered);
  FernOptions options;
  options.keyframe_threshold = 0.0;
  FernDatabase database(options, kWidth, kHeight);
  std::vector<FernFrame> encoded;
  for (int i = 0; i < offered; ++i) {
    encoded.push_back(database.makeFrame());
    database.encode(frames[static_cast<std::size_t>(i)], encoded.back());
    database.addIfNovel(encoded.back(), SE3d(), i, static_cast<std::uint32_t>(i));
  }
  std::size_t next = 0;
  for (auto _ : state) {
    const FernMatch match = database.query(encoded[next].codes, static_cast<std::uint32_t>(offered), 0);
    benchmark::DoNotOptimize(match.keyframe);
    next = (next + 1) % encoded.size();
  }
  state.counters["keyframes"] = database.size();
}

/// A map of `surfels` points on the four walls of a 4 × 3 × 2.5 m room, created in time order along the walls
/// (frames 0 … 599), as a turn about the room maps them.
std::vector<NodeSample> roomMap(int surfels) {
  constexpr std::uint32_t kFrames = 600;
  constexpr double kHalfX_m = 2.0;
  constexpr double kHalfY_m = 1.5;
  constexpr double kHeight_m = 2.5;
  const double perimeter_m = 4.0 * (kHalfX_m + kHalfY_m);
  const int rows = 50;
  const int columns = surfels / rows;
  std::vector<NodeSample> map;
  for (int c = 0; c < columns; ++c) {
    double s = perimeter_m * (c + 0.5) / columns;
    Eigen::Vector2d xy;
    if (s < 2 * kHalfX_m) {
      xy = {-kHalfX_m + s, -kHalfY_m};
    } else if ((s -= 2 * kHalfX_m) < 2 * kHalfY_m) {
      xy = {kHalfX_m, -kHalfY_m + s};
    } else if ((s -= 2 * kHalfY_m) < 2 * kHalfX_m) {
      xy = {kHalfX_m - s, kHalfY_m};
    } else {
      xy = {-kHalfX_m, kHalfY_m - (s - 2 * kHalfX_m)};
    }
    const auto time = static_cast<std::uint32_t>(static_cast<double>(c) / columns * kFrames);
    for (int r = 0; r < rows; ++r) map.push_back({{xy.x(), xy.y(), kHeight_m * (r + 0.5) / rows}, time});
  }
  return map;
}

/// Argument: nodes. One closure: the newest tenth of the map is constrained to a 1° / 2 cm correction and the
/// oldest tenth pinned, 768 points each (the constraint grid at 640×480), gravity term on.
void deformationSolve(benchmark::State& state) {
  constexpr int kGridPoints = 32 * 24;
  const int nodes = static_cast<int>(state.range(0));
  const std::vector<NodeSample> map = roomMap(std::max(20 * nodes, 20'000));
  DeformationGraphOptions options;
  options.max_nodes = nodes;
  options.neighbours_per_side = 4;  // slam::LoopClosureOptions's
  options.max_constraints = 2 * kGridPoints;
  DeformationGraph graph(options);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(std::numbers::pi / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Vector3d tau(0.02, 0.0, 0.0);
  const std::size_t tenth = map.size() / 10;
  const std::size_t step = std::max<std::size_t>(1, tenth / kGridPoints);
  DeformationSolveResult result;
  for (auto _ : state) {
    graph.build(map);
    graph.setGravity(Eigen::Vector3d(0.0, 0.0, -9.81));
    for (std::size_t k = 0; k < static_cast<std::size_t>(kGridPoints); ++k) {
      const NodeSample& newest = map[map.size() - 1 - std::min(tenth - 1, k * step)];
      const NodeSample& oldest = map[std::min(tenth - 1, k * step)];
      graph.addConstraint(newest.p_W, newest.time, R * newest.p_W + tau);
      graph.addPin(oldest.p_W, oldest.time);
    }
    result = graph.solve();
    benchmark::DoNotOptimize(result.iterations);
  }
  state.counters["nodes"] = graph.nodeCount();
  state.counters["constraints"] = graph.constraintCount();
  state.counters["iterations"] = result.iterations;
  state.counters["error_after_mm"] = 1e3 * result.mean_constraint_error_after_m;
}

BENCHMARK(fernEncode)->Name("fern_encode/640x480")->Unit(benchmark::kMillisecond);
BENCHMARK(fernQuery)->Name("fern_query/640x480")->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK(deformationSolve)->Name("deformation_solve")->Arg(256)->Arg(1024)->Arg(4096)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace vifusion::loop

BENCHMARK_MAIN();
