#pragma once
// geometry_msgs/Vector3, Quaternion, Transform, TransformStamped and tf2_msgs/TFMessage: the rig's fixed
// extrinsics, published once on /tf_static. Strings are views (time_header.hpp).
//
// Frames as tf defines them: a TransformStamped with header.frame_id = a and child_frame_id = b holds
// T_a_b, the pose of b in a, which maps points from b to a (p_a = T_a_b · p_b), our own T_a_b convention.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_reader.hpp"
#include "vifusion/ros2_msgs/cdr_writer.hpp"
#include "vifusion/ros2_msgs/definitions.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"

namespace vifusion::ros2_msgs {

struct Vector3 {
  static constexpr std::string_view kTypeName = "geometry_msgs/msg/Vector3";
  static constexpr std::string_view kDefinition = definitions::kVector3;

  double x = 0.0;
  double y = 0.0;
  double z = 0.0;

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const Vector3&) const = default;
};

/// Hamilton unit quaternion, fields in ROS order x, y, z, w (Eigen's coeffs() order too, not its
/// constructor's w, x, y, z). Defaults to the identity, as the .msg file's defaults.
struct Quaternion {
  static constexpr std::string_view kTypeName = "geometry_msgs/msg/Quaternion";
  static constexpr std::string_view kDefinition = definitions::kQuaternion;

  double x = 0.0;
  double y = 0.0;
  double z = 0.0;
  double w = 1.0;

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const Quaternion&) const = default;
};

struct Transform {
  static constexpr std::string_view kTypeName = "geometry_msgs/msg/Transform";
  static constexpr std::string_view kDefinition = definitions::kTransform;

  Vector3 translation;  ///< [m]
  Quaternion rotation;

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const Transform&) const = default;
};

struct TransformStamped {
  static constexpr std::string_view kTypeName = "geometry_msgs/msg/TransformStamped";
  static constexpr std::string_view kDefinition = definitions::kTransformStamped;

  Header header;                    ///< frame_id: the parent frame a
  std::string_view child_frame_id;  ///< the child frame b, a view
  Transform transform;              ///< T_a_b

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const TransformStamped&) const = default;
};

/// tf2_msgs/TFMessage with room for a fixed number of transforms, so that neither direction allocates.
struct TfMessage {
  static constexpr std::string_view kTypeName = "tf2_msgs/msg/TFMessage";
  static constexpr std::string_view kDefinition = definitions::kTfMessage;
  /// Transforms one message holds. A rig's static tree (IMU, depth and colour cameras, base) has 3-4
  /// edges; 16 leaves room for a robot's own frames. Reading a message with more throws.
  static constexpr std::size_t kCapacity = 16;

  std::array<TransformStamped, kCapacity> transforms{};
  std::size_t transform_count = 0;  ///< entries of `transforms` in use, [0, kCapacity]

  /// The transforms in use.
  std::span<const TransformStamped> active() const { return {transforms.data(), transform_count}; }
  /// Appends one; returns false (and changes nothing) when kCapacity are held already.
  bool add(const TransformStamped& transform);

  /// A transform_count over kCapacity fails the writer.
  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  /// Compares the transforms in use only.
  bool operator==(const TfMessage& other) const;
};

}  // namespace vifusion::ros2_msgs
