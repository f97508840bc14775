#pragma once
// The most recent problem the driver thread met (an edge dropped, a failed wait), as text another thread can
// read. Writing formats into a fixed buffer, so the driver thread can say exactly what was wrong without
// touching the heap; the mutex is taken only when a problem is written or read, never for a good edge.

#include <array>
#include <cstddef>
#include <mutex>
#include <string>

namespace vifusion::gpio_sync {

class ProblemNote {
 public:
  /// Longest message kept [characters]; longer ones are cut (the line name and field come first).
  static constexpr std::size_t kCapacity = 255;

  /// printf-style; replaces the previous text. No allocation.
  void set(const char* format, ...) __attribute__((format(printf, 2, 3)));
  void clear();
  /// A copy of the text (empty when none); allocates, so for status readers, not the driver thread.
  std::string text() const;

 private:
  mutable std::mutex mutex_;
  std::array<char, kCapacity + 1> text_{};
};

}  // namespace vifusion::gpio_sync
