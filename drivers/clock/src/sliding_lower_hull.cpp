#include "vifusion/clock/sliding_lower_hull.hpp"

#include <cassert>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::clock {

SlidingLowerHull::SlidingLowerHull(std::size_t capacity) {
  if (capacity < kMinCapacity) {
    throw Error("clock hull: capacity = " + std::to_string(capacity) +
                " points must be >= " + std::to_string(kMinCapacity));
  }
  points_.resize(capacity);
  hull_.resize(capacity);
  scratch_.resize(capacity);
}

void SlidingLowerHull::clear() {
  oldest_id_ = next_id_;
  hull_begin_ = 0;
  hull_size_ = 0;
}

void SlidingLowerHull::push(ClockPoint point) {
  assert(empty() || point.device_ns > newest().device_ns);
  if (size() == capacity()) {
    ++oldest_id_;
    repairFront();
  }
  const std::uint64_t id = next_id_++;
  points_[id % points_.size()] = point;
  while (hull_size_ >= 2 && !strictlyBelow(hullId(hull_size_ - 2), hullId(hull_size_ - 1), id)) --hull_size_;
  hull_[(hull_begin_ + hull_size_) % hull_.size()] = id;
  ++hull_size_;
}

void SlidingLowerHull::expireBefore(std::int64_t oldest_kept_device_ns) {
  const std::uint64_t before = oldest_id_;
  while (!empty() && oldest().device_ns < oldest_kept_device_ns) {
    ++oldest_id_;
  }
  if (oldest_id_ != before) repairFront();
}

std::size_t SlidingLowerHull::edgeAt(std::int64_t device_ns) const {
  assert(hull_size_ >= 2);
  // Binary search for the last vertex at or before device_ns, kept inside [0, hull_size_ − 2].
  std::size_t low = 0;
  std::size_t high = hull_size_ - 2;
  while (low < high) {
    const std::size_t middle = (low + high + 1) / 2;
    if (vertex(middle).device_ns <= device_ns) {
      low = middle;
    } else {
      high = middle - 1;
    }
  }
  return low;
}

std::size_t SlidingLowerHull::supportingVertex(double skew) const {
  assert(hull_size_ >= 1);
  // Along edge i the height host − (1 + skew)·device changes by (Δhost − Δdevice) − skew·Δdevice, and on a
  // lower hull these edge slopes increase: the lowest vertex is the left end of the first edge that does
  // not descend. Binary search over the edges; the 1 of the slope is taken in integers so only the small
  // skew term meets a double.
  std::size_t low = 0;                // first edge that may not descend
  std::size_t high = hull_size_ - 1;  // one past the last edge
  while (low < high) {
    const std::size_t edge = (low + high) / 2;
    const ClockPoint a = vertex(edge);
    const ClockPoint b = vertex(edge + 1);
    const std::int64_t dx_ns = b.device_ns - a.device_ns;
    const bool descends = static_cast<double>((b.host_ns - a.host_ns) - dx_ns) < skew * static_cast<double>(dx_ns);
    if (descends) {
      low = edge + 1;
    } else {
      high = edge;
    }
  }
  return low;
}

bool SlidingLowerHull::strictlyBelow(std::uint64_t left, std::uint64_t middle, std::uint64_t right) const {
  const ClockPoint a = point(left);
  const ClockPoint b = point(middle);
  const ClockPoint c = point(right);
  // Counter-clockwise turn a → b → c, i.e. b under the segment a–c for increasing device_ns.
  const Int128 cross = static_cast<Int128>(b.device_ns - a.device_ns) * (c.host_ns - a.host_ns) -
                       static_cast<Int128>(b.host_ns - a.host_ns) * (c.device_ns - a.device_ns);
  return cross > 0;
}

void SlidingLowerHull::pushOntoScratch(std::uint64_t id) {
  while (scratch_size_ >= 2 && !strictlyBelow(scratch_[scratch_size_ - 2], scratch_[scratch_size_ - 1], id)) {
    --scratch_size_;
  }
  scratch_[scratch_size_++] = id;
}

void SlidingLowerHull::repairFront() {
  if (empty()) {
    hull_begin_ = 0;
    hull_size_ = 0;
    return;
  }
  if (hull_size_ > 0 && hullId(0) >= oldest_id_) return;
  while (hull_size_ > 0 && hullId(0) < oldest_id_) {
    hull_begin_ = (hull_begin_ + 1) % hull_.size();
    --hull_size_;
  }
  // The newest point is always a vertex and never expires while the window holds points.
  assert(hull_size_ > 0);
  scratch_size_ = 0;
  for (std::uint64_t id = oldest_id_; id < hullId(0); ++id) pushOntoScratch(id);
  for (std::size_t i = 0; i < hull_size_; ++i) pushOntoScratch(hullId(i));
  for (std::size_t i = 0; i < scratch_size_; ++i) hull_[i] = scratch_[i];
  hull_begin_ = 0;
  hull_size_ = scratch_size_;
}

}  // namespace vifusion::clock
