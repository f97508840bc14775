#pragma once
// A fixed pool of threads that runs one image-row loop at a time. The threads are started once, in
// the constructor; a job is a pointer to the caller's loop body plus a row counter, so dispatching a
// frame allocates nothing. Rows are handed out in small chunks from an atomic counter: that balances
// views where some rows are expensive (furniture, textures) and others cheap, and results do not
// depend on which thread ran which row as long as each row's work is independent.

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

namespace vifusion::scene {

class RowPool {
 public:
  /// thread_count counts the calling thread, which works too; 0 means std::thread::hardware_concurrency()
  /// (at least 1). thread_count = 1 runs every job on the caller.
  explicit RowPool(int thread_count = 0);
  ~RowPool();
  RowPool(const RowPool&) = delete;
  RowPool& operator=(const RowPool&) = delete;

  int threadCount() const { return static_cast<int>(workers_.size()) + 1; }

  /// Calls body(row_begin, row_end) for consecutive chunks of chunk_rows rows covering [0, rows), on
  /// every thread of the pool, and returns when all are done. body must not throw (there is nowhere
  /// to deliver the exception) and must not call forRows on the same pool. Calls from several threads
  /// are serialised.
  template <class Body>
  void forRows(int rows, const Body& body, int chunk_rows = 4) {
    run(rows, chunk_rows, &invoke<Body>, &body);
  }

 private:
  using Trampoline = void (*)(const void* body, int row_begin, int row_end);

  template <class Body>
  static void invoke(const void* body, int row_begin, int row_end) {
    (*static_cast<const Body*>(body))(row_begin, row_end);
  }

  void run(int rows, int chunk_rows, Trampoline trampoline, const void* body);
  void workerLoop();
  /// Takes chunks of the current job until none are left.
  void drain();

  std::vector<std::thread> workers_;
  std::mutex dispatch_mutex_;  ///< one job at a time
  std::mutex mutex_;           ///< guards generation_, busy_workers_, stop_ and the job fields
  std::condition_variable wake_;
  std::condition_variable done_;
  std::uint64_t generation_ = 0;  ///< incremented per job; workers run each generation once
  int busy_workers_ = 0;          ///< workers that have not yet finished the current generation
  bool stop_ = false;

  Trampoline trampoline_ = nullptr;
  const void* body_ = nullptr;
  int rows_ = 0;
  int chunk_rows_ = 1;
  std::atomic<int> next_row_{0};
};

}  // namespace vifusion::scene
