#pragma once
// A fixed-size message buffer for problems found on the per-frame path (a refused timestamp, a bad
// metadata row). Formatting into it never touches the heap, so a driver thread can say exactly what was
// wrong with a frame without breaking the no-allocation rule; the text is overwritten by the next problem.

#include <array>
#include <cstddef>
#include <string_view>

namespace vifusion::v4l2 {

class ProblemText {
 public:
  /// Longest message kept [characters]; longer ones are cut (they stay readable: the field comes first).
  static constexpr std::size_t kCapacity = 255;

  /// printf-style; replaces the previous text.
  void set(const char* format, ...) __attribute__((format(printf, 2, 3)));
  void clear() { length_ = 0; }

  std::string_view view() const { return {text_.data(), length_}; }
  const char* c_str() const { return text_.data(); }
  bool empty() const { return length_ == 0; }

 private:
  std::array<char, kCapacity + 1> text_{};
  std::size_t length_ = 0;
};

}  // namespace vifusion::v4l2
