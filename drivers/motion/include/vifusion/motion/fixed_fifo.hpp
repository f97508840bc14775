#pragma once
// A first-in first-out queue with a capacity fixed at construction and indexed access, for the IMU
// merger's per-stream buffers: storage is allocated once, pushes and pops only move indices. Single
// thread (the merger's caller); SpscRing is the thread hand-off, this is not.

#include <cassert>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace vifusion::motion {

template <class T>
class FixedFifo {
 public:
  /// @throws std::invalid_argument for capacity 0 (a programming error: options are validated before).
  explicit FixedFifo(std::size_t capacity) : slots_(checkedCapacity(capacity)) {}

  std::size_t size() const { return size_; }
  std::size_t capacity() const { return slots_.size(); }
  bool empty() const { return size_ == 0; }
  bool full() const { return size_ == slots_.size(); }

  /// i-th oldest item. Precondition: i < size().
  const T& operator[](std::size_t i) const {
    assert(i < size_);
    return slots_[(head_ + i) % slots_.size()];
  }
  const T& front() const { return (*this)[0]; }
  const T& back() const { return (*this)[size_ - 1]; }

  /// Appends; returns false (and stores nothing) when full.
  bool pushBack(const T& item) {
    if (full()) return false;
    slots_[(head_ + size_) % slots_.size()] = item;
    ++size_;
    return true;
  }

  /// Removes the oldest item. Precondition: !empty().
  void popFront() {
    assert(!empty());
    head_ = (head_ + 1) % slots_.size();
    --size_;
  }

  void clear() {
    head_ = 0;
    size_ = 0;
  }

 private:
  static std::size_t checkedCapacity(std::size_t capacity) {
    if (capacity == 0) throw std::invalid_argument("FixedFifo: capacity = 0 is invalid (must be >= 1)");
    return capacity;
  }

  std::vector<T> slots_;
  std::size_t head_ = 0;  ///< index of the oldest item
  std::size_t size_ = 0;
};

}  // namespace vifusion::motion
