#pragma once
// The lower convex hull of the (device_ns, host_ns) points in a sliding window, kept up to date as points
// arrive at the right and expire at the left: the data structure behind ClockMapper (clock_mapper.hpp
// says why a lower hull).
//
// Points arrive with strictly increasing device_ns. Adding one is Andrew's monotone chain: pop the hull's
// last vertices while they are not strictly below the segment to the new point, then append it
// (amortised O(1)). Expiring the oldest points is the hard half of a sliding hull: a point popped earlier
// may become a vertex again once the vertices in front of it are gone. Between two vertices that both
// stay, the hull cannot change (the segment joining them is still on the hull of any subset holding
// them), so only the points before the first surviving vertex are scanned again: O(those points + hull
// size) per expiry of a vertex.
//
// Cross products are exact: coordinates are int64 ns and the products are taken in 128 bits, so nearly
// collinear points (low-jitter links) never flip the hull through rounding.
//
// Memory: the point ring, the hull and a scratch chain are sized at construction; nothing allocates
// afterwards. One thread.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vifusion::clock {

/// 128-bit integer for exact products of two int64 differences (GCC and Clang on x86-64 and aarch64;
/// __extension__ keeps -Wpedantic quiet about the non-standard type).
__extension__ typedef __int128 Int128;

/// Largest device or host time a point may carry [ns] (2^61 ns ≈ 73 years): differences of two times
/// and their sums with one window's worth of nanoseconds then stay far inside int64.
inline constexpr std::int64_t kMaxClockTimeNs = std::int64_t{1} << 61;

/// One clock observation: the device's time of a sample and the host time its transfer arrived.
struct ClockPoint {
  std::int64_t device_ns = 0;  ///< device time from the unwrapped ticks [ns]
  std::int64_t host_ns = 0;    ///< host CLOCK_MONOTONIC receive time [ns]
};

class SlidingLowerHull {
 public:
  /// Smallest capacity: a hull needs two points to have an edge.
  static constexpr std::size_t kMinCapacity = 2;

  /// Room for `capacity` points. @throws vifusion::Error naming the capacity when < kMinCapacity.
  explicit SlidingLowerHull(std::size_t capacity);

  /// Forgets every point.
  void clear();

  /// Appends a point. Precondition: point.device_ns > newest().device_ns when not empty (the caller
  /// rejects anything else). When full, the oldest point expires first.
  void push(ClockPoint point);

  /// Expires every point with device_ns < `oldest_kept_device_ns`.
  void expireBefore(std::int64_t oldest_kept_device_ns);

  bool empty() const { return size() == 0; }
  std::size_t size() const { return static_cast<std::size_t>(next_id_ - oldest_id_); }
  std::size_t capacity() const { return points_.size(); }
  /// Precondition for the three below: not empty.
  ClockPoint oldest() const { return point(oldest_id_); }
  ClockPoint newest() const { return point(next_id_ - 1); }

  /// Hull vertices, oldest first; vertex(0) is oldest() and the last one is newest().
  std::size_t vertexCount() const { return hull_size_; }
  ClockPoint vertex(std::size_t index) const { return point(hullId(index)); }

  /// The index i of the hull edge [vertex(i), vertex(i+1)] over `device_ns` (vertex(i).device_ns <=
  /// device_ns < vertex(i+1).device_ns), clamped to the first and last edge. Precondition: vertexCount() >= 2.
  std::size_t edgeAt(std::int64_t device_ns) const;

  /// The vertex with the lowest host_ns − (1 + skew)·device_ns: where a line of slope 1 + skew [host ns
  /// per device ns] touches the hull from below (on a tie, the older vertex). O(log vertexCount()).
  /// Precondition: not empty.
  std::size_t supportingVertex(double skew) const;

 private:
  ClockPoint point(std::uint64_t id) const { return points_[id % points_.size()]; }
  std::uint64_t hullId(std::size_t index) const { return hull_[(hull_begin_ + index) % hull_.size()]; }
  /// True when `middle` lies strictly below the segment from `left` to `right` (a convex turn).
  bool strictlyBelow(std::uint64_t left, std::uint64_t middle, std::uint64_t right) const;
  /// Monotone-chain step onto the scratch chain.
  void pushOntoScratch(std::uint64_t id);
  /// Rebuilds the hull's front after its first vertices expired.
  void repairFront();

  std::vector<ClockPoint> points_;   ///< ring of the window's points, slot = id % capacity
  std::uint64_t oldest_id_ = 0;      ///< id of the oldest point in the window
  std::uint64_t next_id_ = 0;        ///< id the next pushed point gets
  std::vector<std::uint64_t> hull_;  ///< ring of vertex ids, oldest first
  std::size_t hull_begin_ = 0;
  std::size_t hull_size_ = 0;
  std::vector<std::uint64_t> scratch_;  ///< chain rebuilt by repairFront()
  std::size_t scratch_size_ = 0;
};

}  // namespace vifusion::clock
