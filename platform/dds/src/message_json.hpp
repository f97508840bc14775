#pragma once
// JSON for every top-level message, field for field with the ROS 2 field names, as `vifusion echo`
// prints it. Byte sequences (PointCloud2.data) print as their length unless full_arrays is set.

#include "json_line.hpp"
#include "vifusion/dds/messages.hpp"

namespace vifusion::dds::detail {

void writeJson(JsonLine& json, const msg::PoseStamped& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::Odometry& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::TFMessage& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::PointCloud2& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::DiagnosticArray& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::ImuState& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::Status& message, bool full_arrays);
void writeJson(JsonLine& json, const msg::MapSaveRequest& message, bool full_arrays);

}  // namespace vifusion::dds::detail
