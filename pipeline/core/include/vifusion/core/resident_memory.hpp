#pragma once
// Buffers sized at start-up must also be resident from start-up. std::vector::reserve, and resize of a
// type whose default constructor writes nothing (Eigen's fixed-size matrices and vectors), allocate
// address space whose pages the kernel maps only on first write: a solver's factor blocks first filled
// at the first loop closure, an hour into a run, would then grow the process's resident memory (and
// take page faults) in the per-frame path, exactly what a fixed memory budget is meant to rule out.
// These helpers write every element once when the buffer is made.

#include <cstddef>
#include <vector>

namespace vifusion {

/// `values` holds `size` copies of `fill`, every page written.
template <typename T, typename Allocator>
void resizeResident(std::vector<T, Allocator>& values, std::size_t size, const T& fill) {
  values.assign(size, fill);
}

/// `values` is empty with room for `capacity` elements, every page of that room written once.
template <typename T, typename Allocator>
void reserveResident(std::vector<T, Allocator>& values, std::size_t capacity, const T& fill) {
  values.assign(capacity, fill);
  values.clear();  // keeps the capacity and its pages
}

}  // namespace vifusion
