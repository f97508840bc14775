#pragma once
// The topics vifusion publishes (DESIGN.md §5) with their message type and QoS, and the ROS 2 ↔ DDS
// topic-name rule. rmw_cyclonedds maps the ROS topic /a/b to the DDS topic rt/a/b (platform.md §2.1).
//
// QoS (platform.md §2.3): every topic is RELIABLE, KEEP_LAST(depth) and XCDR1. All are VOLATILE except
// the map, which is TRANSIENT_LOCAL with a durability-service history of the same depth, so a viewer
// that starts late (RViz) still receives the last map chunk. A ROS 2 subscriber with default QoS
// (reliable, volatile) matches every one of them.

#include <cstdint>
#include <string>
#include <string_view>

#include "vifusion/dds/messages.hpp"

namespace vifusion::dds {

enum class Durability : std::uint8_t { Volatile, TransientLocal };

struct TopicQos {
  std::int32_t depth = 10;  ///< KEEP_LAST history depth [samples]
  Durability durability = Durability::Volatile;
};

/// A DDS topic carrying messages of type Msg; the type parameter keeps writers and readers honest.
template <typename Msg>
struct Topic {
  std::string_view name;  ///< DDS name, "rt/" + the ROS name without its leading '/'
  TopicQos qos;
};

namespace topics {
inline constexpr Topic<msg::Odometry> kOdometry{"rt/vifusion/odometry", {10, Durability::Volatile}};
inline constexpr Topic<msg::PoseStamped> kPose{"rt/vifusion/pose", {10, Durability::Volatile}};
/// tf2's own defaults: depth 100, volatile.
inline constexpr Topic<msg::TFMessage> kTf{"rt/tf", {100, Durability::Volatile}};
inline constexpr Topic<msg::ImuState> kImuState{"rt/vifusion/imu_state", {10, Durability::Volatile}};
/// Latched like a ROS map (REP-2003): only the last chunk is kept for late joiners.
inline constexpr Topic<msg::PointCloud2> kMap{"rt/vifusion/map", {1, Durability::TransientLocal}};
inline constexpr Topic<msg::Status> kStatus{"rt/vifusion/status", {10, Durability::Volatile}};
/// Requests to save the map now (`vifusion map save`); vifusiond reads it. Depth 1: a request waiting
/// behind a newer one is answered by the newer one's save.
inline constexpr Topic<msg::MapSaveRequest> kMapSaveRequest{"rt/vifusion/map_save_request", {1, Durability::Volatile}};
inline constexpr Topic<msg::DiagnosticArray> kDiagnostics{"rt/diagnostics", {10, Durability::Volatile}};
}  // namespace topics

/// The DDS topic name for a ROS 2 name ("/vifusion/odometry" or "vifusion/odometry", taken as absolute)
/// or an already-mapped DDS name ("rt/vifusion/odometry", returned unchanged). Throws vifusion::Error
/// for an empty name.
std::string ddsTopicName(std::string_view name);

}  // namespace vifusion::dds
