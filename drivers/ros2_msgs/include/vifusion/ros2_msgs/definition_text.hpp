#pragma once
// Compile-time assembly of "ros2msg" definition texts, the MCAP schema encoding of ROS 2 bags, laid out
// as rosbag2 (rosbag2_cpp's LocalMessageDefinitionSource) writes it:
//   the type's .msg text,
//   then for each dependency, depth first, each type once:
//     "\n", a line of 80 '=', "\n", "MSG: <pkg>/<Type>\n", the dependency's .msg text.
// (Our .msg texts end in "\n", so a blank line precedes each separator, as in rosbag2's files.)
// Dependencies are named as the field types spell them ("std_msgs/Header", no "/msg/").

#include <algorithm>
#include <array>
#include <cstddef>
#include <string_view>

namespace vifusion::ros2_msgs {

/// The line between a definition and the next dependency: "\n" + 80 '=' + "\n".
inline constexpr std::string_view kDefinitionSeparator =
    "\n================================================================================\n";
static_assert(kDefinitionSeparator.size() == 80 + 2, "the ros2msg separator line is exactly 80 '='");

/// Concatenation of string_views with static storage, done at compile time: JoinedText<a, b>::kText.
template <const std::string_view&... kParts>
class JoinedText {
  static constexpr std::size_t kSize = (std::size_t{0} + ... + kParts.size());
  static constexpr std::array<char, kSize> join() {
    std::array<char, kSize> chars{};
    auto out = chars.begin();
    ((out = std::copy(kParts.begin(), kParts.end(), out)), ...);
    return chars;
  }
  static constexpr std::array<char, kSize> kChars = join();

 public:
  static constexpr std::string_view kText{kChars.data(), kSize};
};

}  // namespace vifusion::ros2_msgs
