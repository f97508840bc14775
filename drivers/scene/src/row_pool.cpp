#include "vifusion/scene/row_pool.hpp"

#include <algorithm>

namespace vifusion::scene {

RowPool::RowPool(int thread_count) {
  if (thread_count <= 0) thread_count = static_cast<int>(std::max(1U, std::thread::hardware_concurrency()));
  workers_.reserve(static_cast<std::size_t>(thread_count - 1));
  for (int i = 1; i < thread_count; ++i) workers_.emplace_back([this] { workerLoop(); });
}

RowPool::~RowPool() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& worker : workers_) worker.join();
}

void RowPool::run(int rows, int chunk_rows, Trampoline trampoline, const void* body) {
  if (rows <= 0) return;
  std::lock_guard dispatch(dispatch_mutex_);
  {
    std::lock_guard lock(mutex_);
    trampoline_ = trampoline;
    body_ = body;
    rows_ = rows;
    chunk_rows_ = std::max(1, chunk_rows);
    next_row_.store(0, std::memory_order_relaxed);
    busy_workers_ = static_cast<int>(workers_.size());
    ++generation_;
  }
  wake_.notify_all();
  drain();
  // Every worker reports back even if it found no rows left, so the next job cannot start while a
  // slow worker still reads this one's fields.
  std::unique_lock lock(mutex_);
  done_.wait(lock, [this] { return busy_workers_ == 0; });
}

void RowPool::drain() {
  for (;;) {
    const int begin = next_row_.fetch_add(chunk_rows_, std::memory_order_relaxed);
    if (begin >= rows_) return;
    trampoline_(body_, begin, std::min(rows_, begin + chunk_rows_));
  }
}

void RowPool::workerLoop() {
  std::uint64_t seen = 0;
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    lock.unlock();
    drain();
    lock.lock();
    if (--busy_workers_ == 0) done_.notify_one();
  }
}

}  // namespace vifusion::scene
