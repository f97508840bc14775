// Node binding (node_binding.hpp): the time window, the nearest nodes, the weights, the ends of the time
// range, determinism, and float agreeing with double (the GPU shader computes in float).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <vector>

#include "vifusion/loop/node_binding.hpp"

namespace vifusion::loop {
namespace {

constexpr int kCandidates = 20;

struct Nodes {
  std::vector<Eigen::Vector3d> positions;
  std::vector<std::uint32_t> times;
};

/// n nodes scattered in a 2 m cube, two per frame (times 0, 0, 1, 1, …), sorted by time.
Nodes randomNodes(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Nodes nodes;
  for (int i = 0; i < n; ++i) {
    nodes.positions.emplace_back(u(rng), u(rng), u(rng));
    nodes.times.push_back(static_cast<std::uint32_t>(i / 2));
  }
  return nodes;
}

NodeBinding<double> bindD(const Nodes& nodes, const Eigen::Vector3d& p, std::uint32_t time, int candidates) {
  return bindToNodes<double>(p, time, nodes.positions, nodes.times, candidates);
}

TEST(NodeBinding, PicksTheNearestCandidatesWithWeightsSummingToOne) {
  const Nodes nodes = randomNodes(200, 1);
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const auto time = static_cast<std::uint32_t>(trial % 100);
    const NodeBinding<double> b = bindD(nodes, p, time, kCandidates);

    // Brute force over the same window.
    const int start = candidateWindowStart(nodes.times, time, kCandidates);
    std::vector<int> window(kCandidates);
    std::iota(window.begin(), window.end(), start);
    std::stable_sort(window.begin(), window.end(), [&](int a, int c) {
      return (nodes.positions[static_cast<std::size_t>(a)] - p).norm() <
             (nodes.positions[static_cast<std::size_t>(c)] - p).norm();
    });
    const double d_max = (nodes.positions[static_cast<std::size_t>(window[kBoundNodes])] - p).norm();
    double sum = 0.0;
    double raw_sum = 0.0;
    for (int k = 0; k < kBoundNodes; ++k) {
      const double d = (nodes.positions[static_cast<std::size_t>(window[static_cast<std::size_t>(k)])] - p).norm();
      raw_sum += (1.0 - d / d_max) * (1.0 - d / d_max);
    }
    for (int k = 0; k < kBoundNodes; ++k) {
      const auto s = static_cast<std::size_t>(k);
      EXPECT_EQ(b.node[s], window[s]) << "trial " << trial << " slot " << k;
      const double d = (nodes.positions[static_cast<std::size_t>(window[s])] - p).norm();
      EXPECT_NEAR(b.weight[s], (1.0 - d / d_max) * (1.0 - d / d_max) / raw_sum, 1e-12);
      EXPECT_GE(b.weight[s], 0.0);
      sum += b.weight[s];
    }
    EXPECT_NEAR(sum, 1.0, 1e-12);
    // The window is centred on the first node not older than the point.
    const int first =
        static_cast<int>(std::lower_bound(nodes.times.begin(), nodes.times.end(), time) - nodes.times.begin());
    EXPECT_EQ(start, std::clamp(first - kCandidates / 2, 0, 200 - kCandidates));
  }
}

TEST(NodeBinding, WindowIsClampedAtBothEndsOfTheTimeRange) {
  const Nodes nodes = randomNodes(100, 3);
  EXPECT_EQ(candidateWindowStart(nodes.times, 0, kCandidates), 0);
  EXPECT_EQ(candidateWindowStart(nodes.times, 3, kCandidates), 0);
  EXPECT_EQ(candidateWindowStart(nodes.times, 49, kCandidates), 100 - kCandidates);
  EXPECT_EQ(candidateWindowStart(nodes.times, 1'000'000, kCandidates), 100 - kCandidates);
  EXPECT_EQ(candidateWindowStart(nodes.times, 25, kCandidates), 50 - kCandidates / 2);
  // Fewer nodes than candidates: all of them.
  const Nodes few = randomNodes(8, 4);
  EXPECT_EQ(candidateWindowStart(few.times, 2, kCandidates), 0);
  const NodeBinding<double> b = bindD(few, Eigen::Vector3d(0.1, 0.2, 0.3), 2, kCandidates);
  for (int k = 0; k < kBoundNodes; ++k) EXPECT_LT(b.node[static_cast<std::size_t>(k)], 8);
  // Points far outside the time range still bind to the oldest / newest nodes only.
  const NodeBinding<double> late = bindD(nodes, Eigen::Vector3d::Zero(), 1'000'000, kCandidates);
  for (const int i : late.node) EXPECT_GE(i, 100 - kCandidates);
}

TEST(NodeBinding, DegenerateGeometryGivesEqualOrZeroPaddedWeights) {
  // All nodes at one place: d_max = 0 → equal weights.
  Nodes same;
  for (int i = 0; i < 10; ++i) {
    same.positions.emplace_back(1.0, 2.0, 3.0);
    same.times.push_back(static_cast<std::uint32_t>(i));
  }
  const NodeBinding<double> b = bindD(same, Eigen::Vector3d(1.0, 2.0, 3.0), 5, kCandidates);
  for (const double w : b.weight) EXPECT_DOUBLE_EQ(w, 0.25);
  // Ties go to the lower index.
  EXPECT_EQ(b.node[0], 0);
  EXPECT_EQ(b.node[3], 3);

  // Three nodes only: the fourth slot repeats the nearest node with weight 0; weights still sum to 1.
  Nodes three;
  three.positions = {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0, 2, 0)};
  three.times = {0, 1, 2};
  const NodeBinding<double> c = bindD(three, Eigen::Vector3d(0.1, 0, 0), 1, kCandidates);
  EXPECT_EQ(c.node[0], 0);
  EXPECT_EQ(c.node[3], c.node[0]);
  EXPECT_EQ(c.weight[3], 0.0);
  EXPECT_NEAR(c.weight[0] + c.weight[1] + c.weight[2], 1.0, 1e-15);
}

TEST(NodeBinding, IsDeterministicAndFloatAgreesWithDouble) {
  const Nodes nodes = randomNodes(300, 5);
  std::vector<Eigen::Vector3f> positions_f;
  for (const auto& p : nodes.positions) positions_f.push_back(p.cast<float>());
  std::mt19937 rng(6);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int same_nodes = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d p(u(rng), u(rng), u(rng));
    const auto time = static_cast<std::uint32_t>(trial);
    const NodeBinding<double> a = bindD(nodes, p, time, kCandidates);
    const NodeBinding<double> b = bindD(nodes, p, time, kCandidates);
    EXPECT_EQ(a.node, b.node);
    EXPECT_EQ(a.weight, b.weight);
    const NodeBinding<float> f =
        bindToNodes<float>(p.cast<float>(), time, std::span<const Eigen::Vector3f>(positions_f), nodes.times, 20);
    if (f.node == a.node) {
      ++same_nodes;
      for (int k = 0; k < kBoundNodes; ++k) {
        EXPECT_NEAR(f.weight[static_cast<std::size_t>(k)], a.weight[static_cast<std::size_t>(k)], 1e-5);
      }
    }
  }
  // Float may reorder nodes at near-ties of distance; with random positions that is rare.
  EXPECT_GE(same_nodes, 98);
}

}  // namespace
}  // namespace vifusion::loop
