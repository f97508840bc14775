#pragma once
// A human-readable description of a dropped input, held in a fixed array so that describing a problem on
// the driver thread never allocates (a std::string would, once longer than its small-string buffer).

#include <array>
#include <cstdarg>
#include <cstddef>
#include <string_view>

namespace vifusion::motion {

class ProblemText {
 public:
  static constexpr std::size_t kCapacity = 256;  ///< characters kept; longer text is cut, never overflows

  std::string_view view() const { return {chars_.data(), length_}; }

  /// Appends printf-style text, cut at kCapacity − 1 characters.
  [[gnu::format(printf, 2, 3)]] void append(const char* format, ...);

 private:
  std::array<char, kCapacity> chars_{};
  std::size_t length_ = 0;
};

}  // namespace vifusion::motion
