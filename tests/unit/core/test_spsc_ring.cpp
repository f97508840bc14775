#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <new>
#include <stdexcept>
#include <thread>
#include <vector>

#include "vifusion/core/spsc_ring.hpp"

namespace vifusion {
namespace {

TEST(SpscRing, FifoOrderSizeAndEmpty) {
  SpscRing<int> ring(4);
  EXPECT_EQ(ring.capacity(), 4u);
  EXPECT_EQ(ring.size(), 0u);
  int out = -1;
  EXPECT_FALSE(ring.tryPop(out));
  EXPECT_EQ(out, -1);
  EXPECT_EQ(ring.front(), nullptr);

  EXPECT_TRUE(ring.tryPush(10));
  const int twenty = 20;
  EXPECT_TRUE(ring.tryPush(twenty));
  EXPECT_EQ(ring.size(), 2u);
  ASSERT_NE(ring.front(), nullptr);
  EXPECT_EQ(*ring.front(), 10);
  ring.pop();
  EXPECT_TRUE(ring.tryPop(out));
  EXPECT_EQ(out, 20);
  EXPECT_EQ(ring.size(), 0u);
  EXPECT_EQ(ring.overruns(), 0u);

  // Wrap around the storage many times.
  for (int i = 0; i < 1000; ++i) {
    ASSERT_TRUE(ring.tryPush(i));
    ASSERT_TRUE(ring.tryPush(i + 1));
    ASSERT_TRUE(ring.tryPop(out));
    ASSERT_EQ(out, i);
    ASSERT_TRUE(ring.tryPop(out));
    ASSERT_EQ(out, i + 1);
  }
  EXPECT_EQ(ring.overruns(), 0u);
}

TEST(SpscRing, ZeroCapacityIsRejected) { EXPECT_THROW(SpscRing<int>(0), std::invalid_argument); }

TEST(SpscRing, FullRingDropsNewestAndCountsExactly) {
  SpscRing<int> ring(8);
  int accepted = 0;
  for (int i = 0; i < 20; ++i) accepted += ring.tryPush(i) ? 1 : 0;
  EXPECT_EQ(accepted, 8);
  EXPECT_EQ(ring.overruns(), 12u);
  EXPECT_EQ(ring.size(), 8u);
  // The oldest items survive: 0..7, in order.
  int out = -1;
  for (int expected = 0; expected < 8; ++expected) {
    ASSERT_TRUE(ring.tryPop(out));
    EXPECT_EQ(out, expected);
  }
  EXPECT_FALSE(ring.tryPop(out));
  // The counter keeps its history; room is available again.
  EXPECT_TRUE(ring.tryPush(100));
  EXPECT_EQ(ring.overruns(), 12u);
  EXPECT_TRUE(ring.tryPop(out));
  EXPECT_EQ(out, 100);
}

TEST(SpscRing, CapacityOne) {
  SpscRing<std::uint64_t> ring(1);
  std::uint64_t out = 0;
  for (std::uint64_t i = 1; i <= 1000; ++i) {
    ASSERT_TRUE(ring.tryPush(i));
    EXPECT_EQ(ring.size(), 1u);
    ASSERT_FALSE(ring.tryPush(i + 1'000'000));  // full: dropped
    ASSERT_NE(ring.front(), nullptr);
    EXPECT_EQ(*ring.front(), i);
    if (i % 2 == 0) {
      ring.pop();
    } else {
      ASSERT_TRUE(ring.tryPop(out));
      EXPECT_EQ(out, i);
    }
    EXPECT_EQ(ring.size(), 0u);
    EXPECT_EQ(ring.front(), nullptr);
  }
  EXPECT_EQ(ring.overruns(), 1000u);
}

TEST(SpscRing, IndicesLiveOnSeparateCacheLines) {
  // The producer and consumer indices must not share a line (false sharing doubles hand-off cost).
  EXPECT_GE(alignof(SpscRing<int>), 64u);
  EXPECT_GE(sizeof(SpscRing<int>), 3u * 64u);
}

// ---- buffers are reused, not reallocated ----

std::atomic<std::size_t> g_allocations{0};

/// std::allocator that counts allocations, to prove the ring's hand-off does not allocate.
template <class T>
struct CountingAllocator {
  using value_type = T;
  CountingAllocator() = default;
  template <class U>
  CountingAllocator(const CountingAllocator<U>& /*other*/) {}
  T* allocate(std::size_t n) {
    g_allocations.fetch_add(1);
    return std::allocator<T>{}.allocate(n);
  }
  void deallocate(T* p, std::size_t n) { std::allocator<T>{}.deallocate(p, n); }
  bool operator==(const CountingAllocator& /*other*/) const { return true; }
};

/// A frame-like item: not trivially copyable, owns a heap buffer.
struct Frame {
  std::int64_t t_ns = 0;
  std::vector<float, CountingAllocator<float>> pixels;
};

void fill(Frame& frame, std::int64_t t_ns) {
  frame.t_ns = t_ns;
  for (std::size_t i = 0; i < frame.pixels.size(); ++i) frame.pixels[i] = static_cast<float>(t_ns) + 0.5f * i;
}

bool holds(const Frame& frame, std::int64_t t_ns, std::size_t size) {
  if (frame.t_ns != t_ns || frame.pixels.size() != size) return false;
  for (std::size_t i = 0; i < size; ++i) {
    if (frame.pixels[i] != static_cast<float>(t_ns) + 0.5f * i) return false;
  }
  return true;
}

TEST(SpscRing, SwappingPushAndPopCirculateBuffersWithoutAllocating) {
  constexpr std::size_t kPixels = 640 * 48;
  Frame prototype;
  prototype.pixels.resize(kPixels);
  SpscRing<Frame> ring(3, prototype);
  Frame produced = prototype;
  Frame consumed = prototype;

  const std::size_t allocations_before = g_allocations.load();
  for (std::int64_t t = 0; t < 1000; ++t) {
    fill(produced, t);
    ASSERT_TRUE(ring.tryPush(std::move(produced)));
    // The producer got a recycled frame back, with a buffer of the right size to refill.
    ASSERT_EQ(produced.pixels.size(), kPixels);
    if (t % 2 == 1) {  // consume in pairs so the ring holds up to two frames and slots rotate
      ASSERT_TRUE(ring.tryPop(consumed));
      ASSERT_TRUE(holds(consumed, t - 1, kPixels));
      const Frame* in_place = ring.front();
      ASSERT_NE(in_place, nullptr);
      ASSERT_TRUE(holds(*in_place, t, kPixels));
      ring.pop();
    }
  }
  EXPECT_EQ(g_allocations.load(), allocations_before);
}

TEST(SpscRing, CopyingPushReusesSlotBuffers) {
  constexpr std::size_t kPixels = 1000;
  Frame prototype;
  prototype.pixels.resize(kPixels);
  SpscRing<Frame> ring(2, prototype);
  Frame source = prototype;
  Frame consumed = prototype;

  const std::size_t allocations_before = g_allocations.load();
  for (std::int64_t t = 0; t < 1000; ++t) {
    fill(source, t);
    ASSERT_TRUE(ring.tryPush(source));       // copy-assignment into a slot of equal size
    ASSERT_TRUE(holds(source, t, kPixels));  // the source is untouched
    ASSERT_TRUE(ring.tryPop(consumed));
    ASSERT_TRUE(holds(consumed, t, kPixels));
  }
  EXPECT_EQ(g_allocations.load(), allocations_before);
}

TEST(SpscRing, RejectedMovePushLeavesItemWithCaller) {
  SpscRing<Frame> ring(1);
  Frame a;
  a.pixels.assign(3, 1.0f);
  Frame b;
  b.pixels.assign(5, 2.0f);
  ASSERT_TRUE(ring.tryPush(std::move(a)));
  EXPECT_FALSE(ring.tryPush(std::move(b)));
  EXPECT_EQ(b.pixels.size(), 5u);  // dropped, so still ours
  EXPECT_EQ(ring.overruns(), 1u);
  ASSERT_NE(ring.front(), nullptr);
  EXPECT_EQ(ring.front()->pixels.size(), 3u);
}

// ---- real producer and consumer threads ----

/// An item whose two fields must always agree; a torn or stale read breaks the relation.
struct Stamped {
  std::uint64_t sequence = 0;
  std::uint64_t check = 0;
};
constexpr std::uint64_t kCheckFactor = 0x9E3779B97F4A7C15ull;

TEST(SpscRing, MillionItemsArriveInOrderWhenProducerRetries) {
  constexpr std::uint64_t kItems = 1'000'000;
  SpscRing<Stamped> ring(64);
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems; ++i) {
      const Stamped item{i, i * kCheckFactor};
      while (!ring.tryPush(item)) std::this_thread::yield();
    }
  });

  std::uint64_t expected = 0;
  std::uint64_t mismatches = 0;
  Stamped item;
  while (expected < kItems) {
    // Alternate the two consumer APIs.
    if (expected % 2 == 0) {
      if (!ring.tryPop(item)) continue;
    } else {
      const Stamped* front = ring.front();
      if (front == nullptr) continue;
      item = *front;
      ring.pop();
    }
    if (item.sequence != expected || item.check != expected * kCheckFactor) ++mismatches;
    ++expected;
  }
  producer.join();
  EXPECT_EQ(mismatches, 0u);
  EXPECT_EQ(ring.size(), 0u);
  EXPECT_FALSE(ring.tryPop(item));
}

TEST(SpscRing, NonBlockingProducerLosesOnlyCountedItems) {
  constexpr std::uint64_t kItems = 1'000'000;
  SpscRing<Stamped> ring(16);
  std::atomic<bool> producer_done{false};
  std::thread producer([&] {
    for (std::uint64_t i = 0; i < kItems; ++i) ring.tryPush(Stamped{i, i * kCheckFactor});
    producer_done.store(true, std::memory_order_release);
  });

  std::uint64_t received = 0;
  std::uint64_t last = 0;
  bool in_order = true;
  bool consistent = true;
  Stamped item;
  for (;;) {
    const bool done = producer_done.load(std::memory_order_acquire);
    while (ring.tryPop(item)) {
      if (received > 0 && item.sequence <= last) in_order = false;
      if (item.check != item.sequence * kCheckFactor) consistent = false;
      last = item.sequence;
      ++received;
    }
    if (done) break;  // everything pushed before `done` was seen has now been drained
  }
  producer.join();
  EXPECT_TRUE(in_order);
  EXPECT_TRUE(consistent);
  EXPECT_EQ(received + ring.overruns(), kItems);
  EXPECT_GT(received, 0u);
}

}  // namespace
}  // namespace vifusion
