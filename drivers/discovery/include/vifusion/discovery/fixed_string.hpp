#pragma once
// A string with its storage inside the object, for values that must be copied on a path that may not
// allocate (hotplug events): assigning text that does not fit fails instead of growing.

#include <array>
#include <cstddef>
#include <string_view>

namespace vifusion::discovery {

template <std::size_t kCapacity>
class FixedString {
 public:
  static constexpr std::size_t capacity() { return kCapacity; }

  /// Copies `text`; returns false and leaves the string empty when text is longer than kCapacity.
  bool assign(std::string_view text) {
    if (text.size() > kCapacity) {
      size_ = 0;
      return false;
    }
    text.copy(bytes_.data(), text.size());
    size_ = text.size();
    return true;
  }
  void clear() { size_ = 0; }
  bool empty() const { return size_ == 0; }
  std::string_view view() const { return {bytes_.data(), size_}; }

 private:
  std::array<char, kCapacity> bytes_{};
  std::size_t size_ = 0;
};

}  // namespace vifusion::discovery
