#pragma once
// Binding of a point to the deformation graph's nodes (ElasticFusion's rule), the CPU reference of the
// GPU deformation shader. A point — a surfel, a camera position, a constraint's end — with a creation
// time (frame index) is bound to kBoundNodes = 4 nodes:
//
//   1. binary search the time-sorted node list for the first node not older than the point;
//   2. take a window of `candidates` consecutive nodes around that position, shifted (never shrunk) to
//      stay inside [0, node count): nodes made around the same time, so a loop's old and new surfaces,
//      which are close in space but far apart in time, bind to different nodes;
//   3. keep the kBoundNodes nearest candidates by Euclidean distance d_i, ties to the lower index;
//   4. weights w_i = (1 − d_i/d_max)², with d_max the distance to the (kBoundNodes+1)-th nearest
//      candidate, normalised to sum 1. When d_max = 0 or all weights are 0, the kept nodes get equal
//      weights; with fewer than kBoundNodes+1 candidates, d_max is the farthest kept one's distance.
//
// The GLSL shader mirrors these functions step by step, so they are written loop-simple on purpose:
// fixed k, fixed-size arrays, no allocation, no standard algorithms, templated on float and double.
// Unused slots (fewer than kBoundNodes candidates) repeat the nearest node's index with weight 0, so
// the deformation function needs no branch on them.

#include <Eigen/Core>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>

namespace vifusion::loop {

/// Nodes a point is bound to (ElasticFusion's k).
inline constexpr int kBoundNodes = 4;

template <class T>
using Vector3 = Eigen::Matrix<T, 3, 1>;

/// The nodes (indices into the time-sorted node list) and weights (≥ 0, summing to 1) of one point.
template <class T>
struct NodeBinding {
  std::array<std::int32_t, kBoundNodes> node{};
  std::array<T, kBoundNodes> weight{};
};

/// First index of the candidate window of a point with `time`: the window is [start, start + min(candidates,
/// node_times.size())). node_times must be non-decreasing (frame indices).
inline int candidateWindowStart(std::span<const std::uint32_t> node_times, std::uint32_t time, int candidates) {
  const int n = static_cast<int>(node_times.size());
  // Binary search: lo ends at the first node with node_times[lo] >= time (n when all are older).
  int lo = 0;
  int hi = n;
  while (lo < hi) {
    const int mid = lo + (hi - lo) / 2;
    if (node_times[static_cast<std::size_t>(mid)] < time) {
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  const int count = candidates < n ? candidates : n;
  int start = lo - count / 2;
  if (start > n - count) start = n - count;
  if (start < 0) start = 0;
  return start;
}

/// Binds p_W (created at frame `time`) to kBoundNodes nodes, as described at the top of this file.
/// node_positions_W[i] and node_times[i] describe node i (positions in W [m], times non-decreasing);
/// at least one node is required. candidates ≥ kBoundNodes + 1 for ElasticFusion's weights.
template <class T>
NodeBinding<T> bindToNodes(const Vector3<T>& p_W, std::uint32_t time, std::span<const Vector3<T>> node_positions_W,
                           std::span<const std::uint32_t> node_times, int candidates) {
  constexpr int kKept = kBoundNodes + 1;  // the k nearest and the one that sets d_max
  const int n = static_cast<int>(node_times.size());
  const int count = candidates < n ? candidates : n;
  const int start = candidateWindowStart(node_times, time, candidates);

  // Insertion into a sorted list of the kKept nearest (squared distance [m²], node index).
  std::array<T, kKept> best_d2;
  std::array<std::int32_t, kKept> best_node;
  for (int i = 0; i < kKept; ++i) {
    best_d2[static_cast<std::size_t>(i)] = std::numeric_limits<T>::infinity();
    best_node[static_cast<std::size_t>(i)] = -1;
  }
  for (int c = start; c < start + count; ++c) {
    const T d2 = (node_positions_W[static_cast<std::size_t>(c)] - p_W).squaredNorm();
    if (!(d2 < best_d2[kKept - 1])) continue;  // strict: on ties the lower index stays
    int j = kKept - 1;
    while (j > 0 && d2 < best_d2[static_cast<std::size_t>(j - 1)]) {
      best_d2[static_cast<std::size_t>(j)] = best_d2[static_cast<std::size_t>(j - 1)];
      best_node[static_cast<std::size_t>(j)] = best_node[static_cast<std::size_t>(j - 1)];
      --j;
    }
    best_d2[static_cast<std::size_t>(j)] = d2;
    best_node[static_cast<std::size_t>(j)] = c;
  }

  NodeBinding<T> binding;
  const int kept = count < kBoundNodes ? count : kBoundNodes;
  if (kept <= 0) return binding;  // no nodes: all weights 0 (callers require at least one node)
  const T d_max = std::sqrt(count > kBoundNodes ? best_d2[kBoundNodes] : best_d2[static_cast<std::size_t>(kept - 1)]);
  T sum = T(0);
  for (int i = 0; i < kBoundNodes; ++i) {
    const auto s = static_cast<std::size_t>(i);
    if (i < kept) {
      binding.node[s] = best_node[s];
      T w = T(0);
      if (d_max > T(0)) {
        const T u = T(1) - std::sqrt(best_d2[s]) / d_max;
        w = u * u;
      }
      binding.weight[s] = w;
      sum += w;
    } else {
      binding.node[s] = best_node[0];
      binding.weight[s] = T(0);
    }
  }
  for (int i = 0; i < kept; ++i) {
    const auto s = static_cast<std::size_t>(i);
    binding.weight[s] = sum > T(0) ? binding.weight[s] / sum : T(1) / static_cast<T>(kept);
  }
  return binding;
}

}  // namespace vifusion::loop
