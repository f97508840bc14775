#pragma once
// sensor_msgs/Image, Imu, CameraInfo (with RegionOfInterest). Strings and pixel data are views
// (time_header.hpp): an image is serialised straight from the caller's pixels and read back as a span of
// the CDR bytes, never copied into a container.

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

#include "vifusion/ros2_msgs/cdr_reader.hpp"
#include "vifusion/ros2_msgs/cdr_writer.hpp"
#include "vifusion/ros2_msgs/definitions.hpp"
#include "vifusion/ros2_msgs/geometry_tf.hpp"
#include "vifusion/ros2_msgs/time_header.hpp"

namespace vifusion::ros2_msgs {

/// Image.encoding values we write (ROS's sensor_msgs/image_encodings names).
namespace image_encodings {
/// One uint16 per pixel: raw depth in the sensor's units (FrameStamps.depth_scale_m converts to metres),
/// 0 = no measurement.
inline constexpr std::string_view kDepth16 = "16UC1";
/// Three bytes per pixel in memory order R, G, B.
inline constexpr std::string_view kRgb8 = "rgb8";
/// ROS's name for YUYV (V4L2_PIX_FMT_YUYV, FourCC YUY2): bytes Y0 U Y1 V for each pair of pixels, 2 bytes
/// per pixel; the ZR300 colour camera's native format.
inline constexpr std::string_view kYuyv = "yuv422_yuy2";
}  // namespace image_encodings

/// CameraInfo.distortion_model values (sensor_msgs/distortion_models names).
namespace distortion_models {
inline constexpr std::string_view kPlumbBob = "plumb_bob";       ///< d = k1, k2, p1, p2, k3 (OpenCV's radtan)
inline constexpr std::string_view kEquidistant = "equidistant";  ///< d = k1, k2, k3, k4 (Kannala-Brandt fisheye)
}  // namespace distortion_models

/// Covariance element 0 meaning "no estimate of this quantity" (sensor_msgs/Imu's comment): a reader must
/// ignore the associated field. All zeros instead means "estimate given, covariance unknown".
inline constexpr double kCovarianceNoEstimate = -1.0;

/// sensor_msgs/Image over pixels the caller owns.
struct ImageView {
  static constexpr std::string_view kTypeName = "sensor_msgs/msg/Image";
  static constexpr std::string_view kDefinition = definitions::kImage;

  Header header;                       ///< stamp: acquisition time; frame_id: the camera's optical frame
  std::uint32_t height = 0;            ///< rows [px]
  std::uint32_t width = 0;             ///< columns [px]
  std::string_view encoding;           ///< one of image_encodings, a view
  std::uint8_t is_bigendian = 0;       ///< byte order of multi-byte pixels; 0 on our little-endian hosts
  std::uint32_t step = 0;              ///< bytes from one row's start to the next [bytes]
  std::span<const std::uint8_t> data;  ///< step × height bytes

  /// Fails the writer (nothing thrown) when data is not step × height bytes.
  void serialize(CdrWriter& writer) const;
  /// Throws vifusion::Error when data is not step × height bytes.
  void deserialize(CdrReader& reader);
};

/// sensor_msgs/Imu. Defaults say "no orientation estimate" (what an IMU without a filter publishes)
/// and "covariance unknown" for the rates.
struct Imu {
  static constexpr std::string_view kTypeName = "sensor_msgs/msg/Imu";
  static constexpr std::string_view kDefinition = definitions::kImu;
  static constexpr std::size_t kCovarianceSize = 9;  ///< 3×3, row-major about x, y, z
  using Covariance = std::array<double, kCovarianceSize>;

  Header header;  ///< frame_id: the IMU sensor frame S
  Quaternion orientation;
  Covariance orientation_covariance{kCovarianceNoEstimate};
  Vector3 angular_velocity;                     ///< [rad/s]
  Covariance angular_velocity_covariance{};     ///< [rad²/s²]
  Vector3 linear_acceleration;                  ///< specific force [m/s²]
  Covariance linear_acceleration_covariance{};  ///< [m²/s⁴]

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const Imu&) const = default;
};

struct RegionOfInterest {
  static constexpr std::string_view kTypeName = "sensor_msgs/msg/RegionOfInterest";
  static constexpr std::string_view kDefinition = definitions::kRegionOfInterest;

  std::uint32_t x_offset = 0;  ///< [px]
  std::uint32_t y_offset = 0;  ///< [px]
  std::uint32_t height = 0;    ///< [px]; 0 with width 0: the full image
  std::uint32_t width = 0;     ///< [px]
  bool do_rectify = false;

  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  bool operator==(const RegionOfInterest&) const = default;
};

/// sensor_msgs/CameraInfo with a fixed-capacity distortion vector.
struct CameraInfo {
  static constexpr std::string_view kTypeName = "sensor_msgs/msg/CameraInfo";
  static constexpr std::string_view kDefinition = definitions::kCameraInfo;
  /// Longest distortion vector accepted: OpenCV's full model (k1-k6, p1, p2, s1-s4, τx, τy). plumb_bob has
  /// 5, equidistant 4. Reading a message with more throws.
  static constexpr std::size_t kMaxDistortionCoefficients = 14;
  static constexpr std::size_t kIntrinsicsSize = 9;     ///< K: 3×3 row-major
  static constexpr std::size_t kRectificationSize = 9;  ///< R: 3×3 row-major
  static constexpr std::size_t kProjectionSize = 12;    ///< P: 3×4 row-major

  Header header;                      ///< frame_id: the camera's optical frame (x right, y down, z forward)
  std::uint32_t height = 0;           ///< [px]
  std::uint32_t width = 0;            ///< [px]
  std::string_view distortion_model;  ///< one of distortion_models, a view
  std::array<double, kMaxDistortionCoefficients> d{};
  std::size_t d_count = 0;                     ///< coefficients of `d` in use, [0, kMaxDistortionCoefficients]
  std::array<double, kIntrinsicsSize> k{};     ///< [fx 0 cx; 0 fy cy; 0 0 1] [px]
  std::array<double, kRectificationSize> r{};  ///< rectification rotation; identity for a monocular camera
  std::array<double, kProjectionSize> p{};     ///< [fx' 0 cx' Tx; 0 fy' cy' Ty; 0 0 1 0] [px]
  std::uint32_t binning_x = 0;                 ///< 0 or 1: no binning
  std::uint32_t binning_y = 0;
  RegionOfInterest roi;

  /// The coefficients in use.
  std::span<const double> distortion() const { return {d.data(), d_count}; }
  /// Copies `coefficients` into d; returns false (and changes nothing) when there are too many.
  bool setDistortion(std::span<const double> coefficients);

  /// A d_count over kMaxDistortionCoefficients fails the writer.
  void serialize(CdrWriter& writer) const;
  void deserialize(CdrReader& reader);
  /// Compares the distortion coefficients in use only.
  bool operator==(const CameraInfo& other) const;
};

}  // namespace vifusion::ros2_msgs
