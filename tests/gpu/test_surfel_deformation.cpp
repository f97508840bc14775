// The loop closure's deformation of the surfel map on the GPU (map_deform.comp) against its CPU reference
// (deformSurfelsCpu) on a random room of surfels with random, nearly rigid node maps; against the deformation
// graph's own φ in double after a real solve; and the identity leaving the map where it was. Also the node
// capacity and the options' validation.

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <memory>
#include <random>
#include <span>
#include <string>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/loop/deformation_graph.hpp"
#include "vifusion/loop/node_binding.hpp"
#include "vifusion/map/map_buffers.hpp"
#include "vifusion/map/map_export.hpp"
#include "vifusion/map/surfel_deformation.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion {
namespace {

using map::DeformationNode;
using map::Surfel;

const PinholeCamera kCamera = PinholeCamera::create(64, 48, 50, 50, 32, 24);  ///< index map only
constexpr std::uint32_t kFrames = 600;

/// Surfels on the walls of a 4 × 3 × 2.5 m room, created in frame order as a camera turning once in it would
/// (a surfel's creation frame follows its azimuth), with random normals, radii, confidences and colours.
std::vector<Surfel> roomSurfels(std::size_t count, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  std::vector<Surfel> surfels(count);
  for (std::size_t i = 0; i < count; ++i) {
    const float phase = static_cast<float>(i) / static_cast<float>(count);
    const float azimuth = 2.0f * static_cast<float>(M_PI) * phase;
    const Eigen::Vector3f direction(std::cos(azimuth), std::sin(azimuth), 0.0f);
    const float scale =
        std::min(2.0f / std::max(std::abs(direction.x()), 1e-3f), 1.5f / std::max(std::abs(direction.y()), 1e-3f));
    Surfel& s = surfels[i];
    s.position_confidence << scale * direction.x(), scale * direction.y(), 2.5f * unit(random),
        1.0f + 20.0f * unit(random);
    const Eigen::Vector3f n =
        Eigen::Vector3f(unit(random) - 0.5f, unit(random) - 0.5f, unit(random) - 0.5f).normalized();
    s.normal_radius = Eigen::Vector4f(n.x(), n.y(), n.z(), 0.002f + 0.01f * unit(random));
    s.setPackedColour(random() & 0xffffffu);
    s.colour_times.y() = std::floor(phase * kFrames);
    s.colour_times.z() = s.colour_times.y() + std::floor(10.0f * unit(random));
  }
  return surfels;
}

/// Every `stride`-th surfel as a node (sorted by creation frame, as the surfels are), each with a random
/// nearly rigid map: a rotation of up to 3° about a random axis, scaled by up to ±1 %, and up to 5 cm of
/// translation.
std::vector<DeformationNode> randomNodes(std::span<const Surfel> surfels, std::size_t stride, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> symmetric(-1.0, 1.0);
  std::vector<DeformationNode> nodes;
  for (std::size_t i = 0; i < surfels.size(); i += stride) {
    const Eigen::Vector3d axis = Eigen::Vector3d(symmetric(random), symmetric(random), symmetric(random)).normalized();
    const Eigen::Matrix3d A = (1.0 + 0.01 * symmetric(random)) *
                              Eigen::AngleAxisd(3.0 * M_PI / 180.0 * symmetric(random), axis).toRotationMatrix();
    const Eigen::Vector3d t = 0.05 * Eigen::Vector3d(symmetric(random), symmetric(random), symmetric(random));
    const Eigen::Matrix3d A_inverse_transpose = A.inverse().transpose();
    DeformationNode node;
    node.position_time << surfels[i].position_confidence.head<3>(),
        std::bit_cast<float>(static_cast<std::uint32_t>(surfels[i].colour_times.y()));
    for (int c = 0; c < 3; ++c) {
      node.columns[c] << A.col(c).cast<float>(), static_cast<float>(t[c]);
      node.inverse_transpose_columns[c] << A_inverse_transpose.col(c).cast<float>(), 0.0f;
    }
    nodes.push_back(node);
  }
  return nodes;
}

/// A map with its deformation and export on one arena, and an upload path into the current surfel array.
class DeformationRig {
 public:
  DeformationRig(gpu::GpuContext& context, std::uint32_t capacity, const map::SurfelDeformationOptions& options)
      : map_(plan_, mapOptions(capacity), kCamera),
        deformation_(context, plan_, map_, options),
        export_(context, plan_, map_) {
    const std::uint64_t surfel_bytes = std::uint64_t{capacity} * sizeof(Surfel);
    upload_ = plan_.addBuffer("test.surfels", surfel_bytes, gpu::MemoryUse::Upload);
    arena_ = gpu::MemoryArena::create(context, plan_);
    deformation_.build(*arena_);
    export_.build(*arena_);
    map_.reset(*arena_);
    upload_sequence_ = gpu::CommandSequence::create(context, "upload");
    upload_sequence_->record([&](gpu::CommandRecorder& r) {
      r.copyBuffer(arena_->buffer(upload_), arena_->buffer(map_.surfels(0)), surfel_bytes);
      r.computeBarrier();
    });
  }

  void setSurfels(std::span<const Surfel> surfels) {
    std::memcpy(arena_->buffer(upload_).mapped, surfels.data(), surfels.size_bytes());
    upload_sequence_->run();
    map::MapState state;
    state.surfel_count = static_cast<std::uint32_t>(surfels.size());
    std::memcpy(arena_->buffer(map_.state()).mapped, &state, sizeof(state));
  }
  std::vector<Surfel> surfels() {
    std::vector<Surfel> out;
    export_.read(out);
    return out;
  }
  map::SurfelDeformation& deformation() { return deformation_; }

 private:
  static map::MapOptions mapOptions(std::uint32_t capacity) {
    map::MapOptions options;
    options.capacity = capacity;
    return options;
  }

  gpu::CapacityPlan plan_;
  map::MapBuffers map_;
  map::SurfelDeformation deformation_;
  map::MapExport export_;
  gpu::BufferId upload_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::unique_ptr<gpu::CommandSequence> upload_sequence_;
};

/// Everything but position and normal is kept bit for bit.
void expectOnlyGeometryChanged(const Surfel& before, const Surfel& after) {
  EXPECT_EQ(std::bit_cast<std::uint32_t>(before.position_confidence.w()),
            std::bit_cast<std::uint32_t>(after.position_confidence.w()));
  EXPECT_EQ(std::bit_cast<std::uint32_t>(before.normal_radius.w()),
            std::bit_cast<std::uint32_t>(after.normal_radius.w()));
  EXPECT_EQ(0, std::memcmp(before.colour_times.data(), after.colour_times.data(), sizeof(float) * 4));
}

class SurfelDeformationTest : public test::GpuTest {};

TEST_F(SurfelDeformationTest, GpuMatchesTheCpuReference) {
  constexpr std::uint32_t kSurfels = 40'000;
  const std::vector<Surfel> surfels = roomSurfels(kSurfels, 3);
  const std::vector<DeformationNode> nodes = randomNodes(surfels, 97, 4);  // 413 nodes
  map::SurfelDeformationOptions options;
  options.max_nodes = 500;
  options.workgroups = 5;  // fewer invocations than surfels: the grid-stride loop runs several times
  DeformationRig rig(context(), kSurfels + 100, options);
  rig.setSurfels(surfels);
  rig.deformation().setNodes(nodes);
  rig.deformation().apply();
  const std::vector<Surfel> gpu = rig.surfels();

  std::vector<Surfel> cpu = surfels;
  map::deformSurfelsCpu(cpu, nodes, options.candidates);
  ASSERT_EQ(gpu.size(), cpu.size());
  double worst_position_m = 0.0, worst_normal = 0.0, moved_m = 0.0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    worst_position_m = std::max<double>(
        worst_position_m, (gpu[i].position_confidence.head<3>() - cpu[i].position_confidence.head<3>()).norm());
    worst_normal =
        std::max<double>(worst_normal, (gpu[i].normal_radius.head<3>() - cpu[i].normal_radius.head<3>()).norm());
    moved_m += (cpu[i].position_confidence.head<3>() - surfels[i].position_confidence.head<3>()).norm();
    expectOnlyGeometryChanged(surfels[i], gpu[i]);
  }
  EXPECT_GT(moved_m / kSurfels, 0.02) << "the nodes move the surfels by centimetres";
  // Float arithmetic in a different order (FMA, the GPU's sqrt): rounding only.
  EXPECT_LT(worst_position_m, 2e-5);
  EXPECT_LT(worst_normal, 2e-5);
}

// A later closure holds the nodes older than the previous one at the identity: the surfels bound to them alone
// are skipped (left bit for bit, not recomputed through identity maps with rounding), the rest move as the CPU
// reference moves them.
TEST_F(SurfelDeformationTest, SurfelsOfHeldNodesAreLeftBitForBit) {
  constexpr std::uint32_t kSurfels = 30'000;
  const std::vector<Surfel> surfels = roomSurfels(kSurfels, 7);
  std::vector<DeformationNode> nodes = randomNodes(surfels, 97, 8);  // 310 nodes
  constexpr std::uint32_t kFirstMoving = 200;
  for (std::uint32_t i = 0; i < kFirstMoving; ++i) {
    for (int c = 0; c < 3; ++c) {
      nodes[i].columns[c] = Eigen::Vector4f::Unit(c);
      nodes[i].inverse_transpose_columns[c] = Eigen::Vector4f::Unit(c);
    }
  }
  map::SurfelDeformationOptions options;
  options.max_nodes = 400;
  DeformationRig rig(context(), kSurfels, options);
  rig.setSurfels(surfels);
  rig.deformation().setNodes(nodes, kFirstMoving);
  rig.deformation().apply();
  const std::vector<Surfel> gpu = rig.surfels();
  std::vector<Surfel> cpu = surfels;
  map::deformSurfelsCpu(cpu, nodes, options.candidates, kFirstMoving);

  std::vector<std::uint32_t> node_times;
  for (const DeformationNode& node : nodes) node_times.push_back(node.time());
  ASSERT_EQ(gpu.size(), cpu.size());
  std::size_t held = 0;
  double worst_position_m = 0.0;
  for (std::size_t i = 0; i < cpu.size(); ++i) {
    const auto time = static_cast<std::uint32_t>(surfels[i].colour_times.y());
    const int start = loop::candidateWindowStart(node_times, time, static_cast<int>(options.candidates));
    if (start + static_cast<int>(options.candidates) <= static_cast<int>(kFirstMoving)) {
      ++held;
      ASSERT_EQ(0, std::memcmp(&gpu[i], &surfels[i], sizeof(Surfel))) << "surfel " << i;
      ASSERT_EQ(0, std::memcmp(&cpu[i], &surfels[i], sizeof(Surfel))) << "surfel " << i;
    }
    worst_position_m = std::max<double>(
        worst_position_m, (gpu[i].position_confidence.head<3>() - cpu[i].position_confidence.head<3>()).norm());
  }
  // Windows of 20 nodes: the surfels of the first ~190 held nodes (~97 each) stay, those of the last ~110 move.
  EXPECT_GT(held, 170u * 97u);
  EXPECT_LT(held, 200u * 97u);
  EXPECT_LT(worst_position_m, 2e-5);
  EXPECT_THROW(rig.deformation().setNodes(nodes, static_cast<std::uint32_t>(nodes.size()) + 1), Error);
}

// The whole chain: a graph solved for a smooth correction, its committed nodes on the GPU, and every surfel
// where the graph's own φ in double puts it.
TEST_F(SurfelDeformationTest, SurfelsGoWhereTheSolvedGraphPutsThem) {
  constexpr std::uint32_t kSurfels = 20'000;
  const std::vector<Surfel> surfels = roomSurfels(kSurfels, 5);
  std::vector<loop::NodeSample> samples;
  for (const Surfel& s : surfels) {
    samples.push_back({s.position_confidence.head<3>().cast<double>(), static_cast<std::uint32_t>(s.colour_times.y())});
  }
  loop::DeformationGraphOptions graph_options;
  graph_options.max_nodes = 300;
  loop::DeformationGraph graph(graph_options);
  graph.build(samples);
  graph.setGravity(Eigen::Vector3d(0.0, 0.0, -9.81));
  // The newest tenth of the map moved 4 cm sideways and 1° about the vertical, the oldest tenth pinned.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  for (std::size_t i = 0; i < samples.size(); i += 50) {
    const loop::NodeSample& s = samples[i];
    if (i < samples.size() / 10) graph.addPin(s.p_W, s.time);
    if (i > samples.size() * 9 / 10) graph.addConstraint(s.p_W, s.time, R * s.p_W + Eigen::Vector3d(0.04, 0.0, 0.0));
  }
  const loop::DeformationSolveResult result = graph.solve();
  ASSERT_TRUE(result.hasSolution()) << loop::deformationSolveStatusName(result.status);
  graph.commit();

  map::SurfelDeformationOptions options;
  options.max_nodes = static_cast<std::uint32_t>(graph_options.max_nodes);
  options.candidates = static_cast<std::uint32_t>(graph_options.candidates);
  DeformationRig rig(context(), kSurfels, options);
  rig.setSurfels(surfels);
  rig.deformation().setNodes(graph);
  rig.deformation().apply();
  const std::vector<Surfel> gpu = rig.surfels();
  ASSERT_EQ(gpu.size(), surfels.size());
  double worst_m = 0.0, largest_move_m = 0.0;
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    const Eigen::Vector3d expected = graph.deformPoint(samples[i].p_W, samples[i].time);
    worst_m = std::max(worst_m, (gpu[i].position_confidence.head<3>().cast<double>() - expected).norm());
    largest_move_m = std::max(largest_move_m, (expected - samples[i].p_W).norm());
    const Eigen::Vector3d n = surfels[i].normal_radius.head<3>().cast<double>();
    const Eigen::Vector3d expected_n = graph.deformNormal(n, samples[i].p_W, samples[i].time);
    EXPECT_LT((gpu[i].normal_radius.head<3>().cast<double>() - expected_n).norm(), 1e-4) << "surfel " << i;
  }
  EXPECT_GT(largest_move_m, 0.03);
  EXPECT_LT(worst_m, 1e-4) << "float against double, metres from the origin";
}

TEST_F(SurfelDeformationTest, IdentityNodesLeaveTheMapWhereItWas) {
  constexpr std::uint32_t kSurfels = 5'000;
  const std::vector<Surfel> surfels = roomSurfels(kSurfels, 7);
  std::vector<DeformationNode> nodes = randomNodes(surfels, 50, 8);
  for (DeformationNode& node : nodes) {
    for (int c = 0; c < 3; ++c) {
      node.columns[c] = Eigen::Vector4f::Unit(c);
      node.inverse_transpose_columns[c] = Eigen::Vector4f::Unit(c);
    }
  }
  DeformationRig rig(context(), kSurfels, {});
  rig.setSurfels(surfels);
  rig.deformation().setNodes(nodes);
  rig.deformation().apply();
  const std::vector<Surfel> gpu = rig.surfels();
  for (std::size_t i = 0; i < surfels.size(); ++i) {
    EXPECT_LT((gpu[i].position_confidence.head<3>() - surfels[i].position_confidence.head<3>()).norm(), 1e-6);
    EXPECT_LT((gpu[i].normal_radius.head<3>() - surfels[i].normal_radius.head<3>()).norm(), 1e-6);
    expectOnlyGeometryChanged(surfels[i], gpu[i]);
  }
}

TEST_F(SurfelDeformationTest, NodeCountIsCheckedAgainstTheCapacity) {
  map::SurfelDeformationOptions options;
  options.max_nodes = 10;
  DeformationRig rig(context(), 100, options);
  const std::vector<Surfel> surfels = roomSurfels(100, 9);
  test::expectError([&] { rig.deformation().setNodes(randomNodes(surfels, 5, 1)); }, "max_nodes");
  test::expectError([&] { rig.deformation().setNodes(std::span<const DeformationNode>()); }, "max_nodes");
  map::SurfelDeformationOptions bad;
  bad.candidates = 0;
  test::expectError([&] { bad.validate(); }, "surfel deformation option 'candidates'");
}

}  // namespace
}  // namespace vifusion
