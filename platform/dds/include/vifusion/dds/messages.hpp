#pragma once
// The ROS 2 message types vifusion publishes, as the C structs idlc generates from platform/dds/idl
// (IDL module path pkg::msg::dds_::Type_ → C name pkg_msg_dds__Type_), with short C++ names and the
// type descriptor each topic needs.
//
// Strings are `char*` and sequences are {_maximum, _length, _buffer, _release}. Messages built by
// conversions.hpp BORROW their strings and buffers (_release = false): Cyclone only reads them while
// serialising in Writer::write, so publishing copies nothing of ours and allocates nothing of ours.

#include "vifusion/dds/idl/builtin_interfaces.h"
#include "vifusion/dds/idl/diagnostic_msgs.h"
#include "vifusion/dds/idl/geometry_msgs.h"
#include "vifusion/dds/idl/nav_msgs.h"
#include "vifusion/dds/idl/sensor_msgs.h"
#include "vifusion/dds/idl/std_msgs.h"
#include "vifusion/dds/idl/tf2_msgs.h"
#include "vifusion/dds/idl/vifusion_msgs.h"

namespace vifusion::dds::msg {

using Time = builtin_interfaces_msg_dds__Time_;
using Header = std_msgs_msg_dds__Header_;
using Point = geometry_msgs_msg_dds__Point_;
using Quaternion = geometry_msgs_msg_dds__Quaternion_;
using Vector3 = geometry_msgs_msg_dds__Vector3_;
using Pose = geometry_msgs_msg_dds__Pose_;
using PoseWithCovariance = geometry_msgs_msg_dds__PoseWithCovariance_;
using Twist = geometry_msgs_msg_dds__Twist_;
using TwistWithCovariance = geometry_msgs_msg_dds__TwistWithCovariance_;
using PoseStamped = geometry_msgs_msg_dds__PoseStamped_;
using Transform = geometry_msgs_msg_dds__Transform_;
using TransformStamped = geometry_msgs_msg_dds__TransformStamped_;
using Odometry = nav_msgs_msg_dds__Odometry_;
using TFMessage = tf2_msgs_msg_dds__TFMessage_;
using PointField = sensor_msgs_msg_dds__PointField_;
using PointCloud2 = sensor_msgs_msg_dds__PointCloud2_;
using KeyValue = diagnostic_msgs_msg_dds__KeyValue_;
using DiagnosticStatus = diagnostic_msgs_msg_dds__DiagnosticStatus_;
using DiagnosticArray = diagnostic_msgs_msg_dds__DiagnosticArray_;
using ImuState = vifusion_msgs_msg_dds__ImuState_;
using RingCounters = vifusion_msgs_msg_dds__RingCounters_;
using Status = vifusion_msgs_msg_dds__Status_;
using MapSaveRequest = vifusion_msgs_msg_dds__MapSaveRequest_;

/// vifusion_msgs/Status tracking_state values.
enum class TrackingState : std::uint8_t {
  Ok = vifusion_msgs_msg_Status_Constants_TRACKING_OK,
  Lost = vifusion_msgs_msg_Status_Constants_TRACKING_LOST,
  Initialising = vifusion_msgs_msg_Status_Constants_TRACKING_INITIALISING,
  ImuCarried = vifusion_msgs_msg_Status_Constants_TRACKING_IMU_CARRIED,
  Relocalising = vifusion_msgs_msg_Status_Constants_TRACKING_RELOCALISING,
};

/// The idlc descriptor of a top-level message type: its DDS type name, size and serialiser ops.
template <typename Msg>
struct Descriptor;

template <>
struct Descriptor<PoseStamped> {
  static const dds_topic_descriptor_t& get() { return geometry_msgs_msg_dds__PoseStamped__desc; }
};
template <>
struct Descriptor<Odometry> {
  static const dds_topic_descriptor_t& get() { return nav_msgs_msg_dds__Odometry__desc; }
};
template <>
struct Descriptor<TFMessage> {
  static const dds_topic_descriptor_t& get() { return tf2_msgs_msg_dds__TFMessage__desc; }
};
template <>
struct Descriptor<PointCloud2> {
  static const dds_topic_descriptor_t& get() { return sensor_msgs_msg_dds__PointCloud2__desc; }
};
template <>
struct Descriptor<DiagnosticArray> {
  static const dds_topic_descriptor_t& get() { return diagnostic_msgs_msg_dds__DiagnosticArray__desc; }
};
template <>
struct Descriptor<ImuState> {
  static const dds_topic_descriptor_t& get() { return vifusion_msgs_msg_dds__ImuState__desc; }
};
template <>
struct Descriptor<Status> {
  static const dds_topic_descriptor_t& get() { return vifusion_msgs_msg_dds__Status__desc; }
};
template <>
struct Descriptor<MapSaveRequest> {
  static const dds_topic_descriptor_t& get() { return vifusion_msgs_msg_dds__MapSaveRequest__desc; }
};

}  // namespace vifusion::dds::msg
