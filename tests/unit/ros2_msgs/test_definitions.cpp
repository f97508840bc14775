// The ros2msg texts: rosbag2's layout (separator, "MSG: " lines, dependency order) and ROS 2's type names.
// That Foxglove's parser accepts them and decodes our bytes with them is the node test's job.

#include <gtest/gtest.h>

#include <string>
#include <string_view>
#include <vector>

#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/sensor_msgs.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"
#include "vifusion/ros2_msgs/vifusion_msgs.hpp"

namespace vifusion::ros2_msgs {
namespace {

/// The type names after each "MSG: ", in order.
std::vector<std::string> dependencyNames(std::string_view definition) {
  std::vector<std::string> names;
  const std::string_view marker = "\nMSG: ";
  for (std::size_t at = definition.find(marker); at != std::string_view::npos; at = definition.find(marker, at + 1)) {
    const std::size_t start = at + marker.size();
    names.emplace_back(definition.substr(start, definition.find('\n', start) - start));
  }
  return names;
}

TEST(Definitions, HeaderIsItsTextThenTimeAfterAnEightyEqualsSeparator) {
  const std::string expected =
      "builtin_interfaces/Time stamp\n"
      "string frame_id\n"
      "\n" +
      std::string(80, '=') +
      "\n"
      "MSG: builtin_interfaces/Time\n"
      "int32 sec\n"
      "uint32 nanosec\n";
  EXPECT_EQ(Header::kDefinition, expected);
}

TEST(Definitions, DependenciesFollowRosbag2sDepthFirstSortedOrderOnceEach) {
  using Names = std::vector<std::string>;
  EXPECT_EQ(dependencyNames(Time::kDefinition), Names{});
  EXPECT_EQ(dependencyNames(ImageView::kDefinition), (Names{"std_msgs/Header", "builtin_interfaces/Time"}));
  EXPECT_EQ(dependencyNames(Imu::kDefinition),
            (Names{"geometry_msgs/Quaternion", "geometry_msgs/Vector3", "std_msgs/Header", "builtin_interfaces/Time"}));
  EXPECT_EQ(dependencyNames(CameraInfo::kDefinition),
            (Names{"sensor_msgs/RegionOfInterest", "std_msgs/Header", "builtin_interfaces/Time"}));
  EXPECT_EQ(dependencyNames(TfMessage::kDefinition),
            (Names{"geometry_msgs/TransformStamped", "geometry_msgs/Transform", "geometry_msgs/Quaternion",
                   "geometry_msgs/Vector3", "std_msgs/Header", "builtin_interfaces/Time"}));
  for (std::string_view definition : {FrameStamps::kDefinition, MotionPacket::kDefinition, SyncEdge::kDefinition,
                                      ClockMapping::kDefinition, RecordingInfo::kDefinition}) {
    EXPECT_EQ(dependencyNames(definition), (Names{"std_msgs/Header", "builtin_interfaces/Time"}));
  }
}

TEST(Definitions, EachSeparatorIsExactlyEightyEqualsOnItsOwnLine) {
  const std::string separator = "\n" + std::string(80, '=') + "\nMSG: ";
  const std::string_view text = TfMessage::kDefinition;
  std::size_t separators = 0;
  for (std::size_t at = text.find(separator); at != std::string_view::npos; at = text.find(separator, at + 1)) {
    ++separators;
  }
  EXPECT_EQ(separators, 6u);
  EXPECT_EQ(text.find(std::string(81, '=')), std::string_view::npos);
}

TEST(Definitions, TypeNamesAreRos2sPackageMsgTypeForm) {
  EXPECT_EQ(ImageView::kTypeName, "sensor_msgs/msg/Image");
  EXPECT_EQ(Imu::kTypeName, "sensor_msgs/msg/Imu");
  EXPECT_EQ(CameraInfo::kTypeName, "sensor_msgs/msg/CameraInfo");
  EXPECT_EQ(TransformStamped::kTypeName, "geometry_msgs/msg/TransformStamped");
  EXPECT_EQ(TfMessage::kTypeName, "tf2_msgs/msg/TFMessage");
  EXPECT_EQ(Header::kTypeName, "std_msgs/msg/Header");
  EXPECT_EQ(Time::kTypeName, "builtin_interfaces/msg/Time");
  EXPECT_EQ(FrameStamps::kTypeName, "vifusion_msgs/msg/FrameStamps");
  EXPECT_EQ(ClockMapping::kTypeName, "vifusion_msgs/msg/ClockMapping");
}

TEST(Definitions, DefinitionsStartWithTheTypesOwnFieldsAndEndInANewline) {
  EXPECT_TRUE(ImageView::kDefinition.starts_with("std_msgs/Header header\nuint32 height\n"));
  EXPECT_TRUE(Imu::kDefinition.starts_with("std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"));
  EXPECT_TRUE(TfMessage::kDefinition.starts_with("geometry_msgs/TransformStamped[] transforms\n"));
  EXPECT_NE(ClockMapping::kDefinition.find("uint8 STATE_VALID=2"), std::string_view::npos);
  for (std::string_view definition : {ImageView::kDefinition, Imu::kDefinition, CameraInfo::kDefinition,
                                      TfMessage::kDefinition, RecordingInfo::kDefinition}) {
    EXPECT_TRUE(definition.ends_with("uint32 nanosec\n"));
  }
}

}  // namespace
}  // namespace vifusion::ros2_msgs
