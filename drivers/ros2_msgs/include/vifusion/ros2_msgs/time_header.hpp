#pragma once
// builtin_interfaces/Time and std_msgs/Header, the stamp and frame of every message here.
//
// Strings in these structs are views: serialising reads the characters the caller points to (which must
// live until serialize() returns); deserialising points into the CDR bytes (valid while they live). So
// neither direction allocates.

#include <cstdint>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_reader.hpp"
#include "vifusion/ros2_msgs/cdr_writer.hpp"
#include "vifusion/ros2_msgs/definitions.hpp"

namespace vifusion::ros2_msgs {

/// A time as whole seconds plus nanoseconds in [0, 1e9): −1.7 s is {sec −2, nanosec 300000000}. Our stamps
/// are host CLOCK_MONOTONIC [ns] (DESIGN.md §3), written as they are (no shift to the Unix epoch).
struct Time {
  static constexpr std::string_view kTypeName = "builtin_interfaces/msg/Time";
  static constexpr std::string_view kDefinition = definitions::kTime;

  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;  ///< [0, 999999999]

  /// Splits t_ns with floor division, so negative times keep nanosec in [0, 1e9). Throws vifusion::Error
  /// when the seconds leave int32 (|t| beyond ~68 years, e.g. a Unix-epoch time after January 2038).
  static Time fromNs(std::int64_t t_ns);
  /// sec·1e9 + nanosec [ns]; exact for every valid Time (|sec·1e9| < 2.2e18 fits int64).
  std::int64_t toNs() const;

  void serialize(CdrWriter& writer) const;
  /// Throws vifusion::Error when nanosec is 1e9 or more.
  void deserialize(CdrReader& reader);

  bool operator==(const Time&) const = default;
};

struct Header {
  static constexpr std::string_view kTypeName = "std_msgs/msg/Header";
  static constexpr std::string_view kDefinition = definitions::kHeader;

  Time stamp;
  std::string_view frame_id;  ///< the coordinate frame of the data (a tf frame name), a view

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);

  bool operator==(const Header&) const = default;
};

/// A header at t_ns [host CLOCK_MONOTONIC ns] in frame `frame_id` (a view; see the file comment).
Header makeHeader(std::int64_t t_ns, std::string_view frame_id);

}  // namespace vifusion::ros2_msgs
