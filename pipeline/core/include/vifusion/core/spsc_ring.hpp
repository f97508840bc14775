#pragma once
// Fixed-capacity, lock-free single-producer/single-consumer ring: the hand-off between a driver thread
// (producer) and the SLAM thread (consumer), and between the SLAM thread and the publisher.
//
// When full, the ring DROPS THE NEWEST item and counts it as an overrun:
//  - the producer is a sensor thread that must never wait (a blocked V4L2/USB reader loses data in the
//    kernel instead, uncounted), and
//  - overwriting the oldest item would make the producer move the consumer's read index and race with
//    a consumer that is reading that slot in place (front()); every index would need a second writer.
// Dropping the newest keeps each index single-writer and the consumer's view stable; a consumer that
// is behind loses the same amount of data either way, and overruns() makes the loss visible.
//
// Memory: all slots are constructed in the constructor and only assigned or swapped afterwards. With
// the swapping push/pop overloads a slot's heap buffers (e.g. image storage) circulate between the
// producer, the ring and the consumer, so a steady-state hand-off allocates nothing.

#include <atomic>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <utility>
#include <vector>

namespace vifusion {

template <class T>
class SpscRing {
 public:
  /// `capacity` value-initialised slots. Throws std::invalid_argument for capacity 0.
  explicit SpscRing(std::size_t capacity) : capacity_(checkedCapacity(capacity)), slots_(capacity_) {}
  /// `capacity` copies of `prototype`: pass an item with its buffers already sized so pushes reuse them.
  SpscRing(std::size_t capacity, const T& prototype)
      : capacity_(checkedCapacity(capacity)), slots_(capacity_, prototype) {}
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  // ---- producer thread only ----

  /// Copies `item` into the next slot (copy-assignment, so the slot's buffers are reused).
  /// Returns false and counts an overrun when full.
  bool tryPush(const T& item) {
    T* slot = producerSlot();
    if (slot == nullptr) return false;
    *slot = item;
    publish();
    return true;
  }

  /// Swaps `item` into the next slot; on success `item` receives the slot's previous contents, a
  /// recycled object whose buffers the producer can refill without allocating. Returns false, leaving
  /// `item` untouched, and counts an overrun when full.
  bool tryPush(T&& item) {
    T* slot = producerSlot();
    if (slot == nullptr) return false;
    using std::swap;
    swap(*slot, item);
    publish();
    return true;
  }

  // ---- consumer thread only ----

  /// Swaps the oldest item into `out` (the slot keeps out's old contents for reuse) and removes it.
  /// Returns false when empty.
  bool tryPop(T& out) {
    T* slot = consumerSlot();
    if (slot == nullptr) return false;
    using std::swap;
    swap(out, *slot);
    release();
    return true;
  }

  /// The oldest item, read in place, or nullptr when empty. Valid until pop().
  const T* front() { return consumerSlot(); }

  /// Removes the item front() returned. Precondition: front() != nullptr.
  void pop() {
    const bool has_item = consumerSlot() != nullptr;
    assert(has_item);
    if (has_item) release();
  }

  // ---- any thread ----

  /// Items currently queued; a snapshot that may be stale by the time it is used.
  std::size_t size() const {
    // Tail first: head only grows, so head − tail cannot underflow; it can exceed the capacity if
    // both sides moved between the loads, hence the clamp.
    const std::uint64_t tail = tail_.load(std::memory_order_acquire);
    const std::uint64_t head = head_.load(std::memory_order_acquire);
    const std::uint64_t n = head - tail;
    return n < capacity_ ? static_cast<std::size_t>(n) : capacity_;
  }
  std::size_t capacity() const { return capacity_; }
  /// Items dropped because the ring was full, since construction.
  std::uint64_t overruns() const { return overruns_.load(std::memory_order_relaxed); }

 private:
  // Not std::hardware_destructive_interference_size: GCC warns that it may differ between
  // translation units; 64 bytes is the line size of every target (x86-64, Cortex-A53/A72/A76).
  static constexpr std::size_t kCacheLineBytes = 64;

  static std::size_t checkedCapacity(std::size_t capacity) {
    if (capacity == 0) throw std::invalid_argument("SpscRing: capacity = 0 is invalid (must be >= 1)");
    return capacity;
  }

  T* producerSlot() {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_cache_ == capacity_) {
      // Acquire pairs with the consumer's release: its reads of the slot happen before we overwrite it.
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head - tail_cache_ == capacity_) {
        overruns_.fetch_add(1, std::memory_order_relaxed);
        return nullptr;
      }
    }
    return &slots_[static_cast<std::size_t>(head % capacity_)];
  }

  void publish() {
    // Release: the slot's contents are visible before the consumer sees the new head.
    head_.store(head_.load(std::memory_order_relaxed) + 1, std::memory_order_release);
  }

  T* consumerSlot() {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_cache_) {
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail == head_cache_) return nullptr;
    }
    return &slots_[static_cast<std::size_t>(tail % capacity_)];
  }

  void release() { tail_.store(tail_.load(std::memory_order_relaxed) + 1, std::memory_order_release); }

  // 64-bit running counts (slot = count % capacity) never wrap in practice and let all `capacity`
  // slots be used, which an index pair modulo capacity cannot (full and empty would look alike).

  // Producer's cache line.
  alignas(kCacheLineBytes) std::atomic<std::uint64_t> head_{0};  ///< items pushed so far
  std::uint64_t tail_cache_ = 0;                                 ///< producer's last view of tail_
  std::atomic<std::uint64_t> overruns_{0};                       ///< items dropped because full
  // Consumer's cache line.
  alignas(kCacheLineBytes) std::atomic<std::uint64_t> tail_{0};  ///< items popped so far
  std::uint64_t head_cache_ = 0;                                 ///< consumer's last view of head_
  // Read-only after construction (the slot contents are handed over through head_/tail_).
  alignas(kCacheLineBytes) const std::size_t capacity_;
  std::vector<T> slots_;
};

}  // namespace vifusion
