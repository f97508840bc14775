#pragma once
// The message types fuzz_cdr_messages reads, in the order its first input byte chooses them; the seed writer
// (seeds/cdr_seeds.cpp) uses the same list, so each seed starts with its type's index.

#include <tuple>

#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"
#include "vifusion/ros2_msgs/vifusion_msgs.hpp"

namespace vifusion::fuzz {

using CdrMessageTypes =
    std::tuple<ros2_msgs::Time, ros2_msgs::Header, ros2_msgs::ImageView, ros2_msgs::Imu, ros2_msgs::RegionOfInterest,
               ros2_msgs::CameraInfo, ros2_msgs::Vector3, ros2_msgs::Quaternion, ros2_msgs::Transform,
               ros2_msgs::TransformStamped, ros2_msgs::TfMessage, ros2_msgs::FrameStamps, ros2_msgs::MotionPacket,
               ros2_msgs::SyncEdge, ros2_msgs::ClockMapping, ros2_msgs::RecordingInfo>;

/// Index of `Message` in CdrMessageTypes.
template <typename Message, std::size_t I = 0>
constexpr std::size_t cdrTypeIndex() {
  if constexpr (std::is_same_v<std::tuple_element_t<I, CdrMessageTypes>, Message>) {
    return I;
  } else {
    return cdrTypeIndex<Message, I + 1>();
  }
}

}  // namespace vifusion::fuzz
