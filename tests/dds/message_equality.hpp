#pragma once
// Field-by-field exact equality of messages (doubles bit for bit: a round trip must not round).
// Each check names the field path on failure.

#include <gtest/gtest.h>

#include <cstring>
#include <string>

#include "vifusion/dds/messages.hpp"

namespace vifusion::dds::test {

inline void expectSameString(const char* a, const char* b, const std::string& path) {
  ASSERT_NE(a, nullptr) << path;
  ASSERT_NE(b, nullptr) << path;
  EXPECT_STREQ(a, b) << path;
}

template <std::size_t N>
void expectSameArray(const double (&a)[N], const double (&b)[N], const std::string& path) {
  for (std::size_t i = 0; i < N; ++i) EXPECT_EQ(a[i], b[i]) << path << "[" << i << "]";
}

/// Sequences: equal lengths, then `same(a[i], b[i], path[i])` for every element.
template <typename Sequence, typename Same>
void expectSameSequence(const Sequence& a, const Sequence& b, const std::string& path, Same&& same) {
  ASSERT_EQ(a._length, b._length) << path << "._length";
  for (std::uint32_t i = 0; i < a._length; ++i) same(a._buffer[i], b._buffer[i], path + "[" + std::to_string(i) + "]");
}

inline void expectSame(const msg::Time& a, const msg::Time& b, const std::string& path) {
  EXPECT_EQ(a.sec, b.sec) << path << ".sec";
  EXPECT_EQ(a.nanosec, b.nanosec) << path << ".nanosec";
}

inline void expectSame(const msg::Header& a, const msg::Header& b, const std::string& path) {
  expectSame(a.stamp, b.stamp, path + ".stamp");
  expectSameString(a.frame_id, b.frame_id, path + ".frame_id");
}

inline void expectSame(const msg::Vector3& a, const msg::Vector3& b, const std::string& path) {
  EXPECT_EQ(a.x, b.x) << path << ".x";
  EXPECT_EQ(a.y, b.y) << path << ".y";
  EXPECT_EQ(a.z, b.z) << path << ".z";
}

inline void expectSame(const msg::Point& a, const msg::Point& b, const std::string& path) {
  EXPECT_EQ(a.x, b.x) << path << ".x";
  EXPECT_EQ(a.y, b.y) << path << ".y";
  EXPECT_EQ(a.z, b.z) << path << ".z";
}

inline void expectSame(const msg::Quaternion& a, const msg::Quaternion& b, const std::string& path) {
  EXPECT_EQ(a.x, b.x) << path << ".x";
  EXPECT_EQ(a.y, b.y) << path << ".y";
  EXPECT_EQ(a.z, b.z) << path << ".z";
  EXPECT_EQ(a.w, b.w) << path << ".w";
}

inline void expectSame(const msg::Pose& a, const msg::Pose& b, const std::string& path) {
  expectSame(a.position, b.position, path + ".position");
  expectSame(a.orientation, b.orientation, path + ".orientation");
}

inline void expectSame(const msg::Transform& a, const msg::Transform& b, const std::string& path) {
  expectSame(a.translation, b.translation, path + ".translation");
  expectSame(a.rotation, b.rotation, path + ".rotation");
}

inline void expectSame(const msg::PoseStamped& a, const msg::PoseStamped& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  expectSame(a.pose, b.pose, path + ".pose");
}

inline void expectSame(const msg::TransformStamped& a, const msg::TransformStamped& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  expectSameString(a.child_frame_id, b.child_frame_id, path + ".child_frame_id");
  expectSame(a.transform, b.transform, path + ".transform");
}

inline void expectSame(const msg::Odometry& a, const msg::Odometry& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  expectSameString(a.child_frame_id, b.child_frame_id, path + ".child_frame_id");
  expectSame(a.pose.pose, b.pose.pose, path + ".pose.pose");
  expectSameArray(a.pose.covariance, b.pose.covariance, path + ".pose.covariance");
  expectSame(a.twist.twist.linear, b.twist.twist.linear, path + ".twist.twist.linear");
  expectSame(a.twist.twist.angular, b.twist.twist.angular, path + ".twist.twist.angular");
  expectSameArray(a.twist.covariance, b.twist.covariance, path + ".twist.covariance");
}

inline void expectSame(const msg::TFMessage& a, const msg::TFMessage& b, const std::string& path) {
  expectSameSequence(a.transforms, b.transforms, path + ".transforms",
                     [](const auto& x, const auto& y, const std::string& p) { expectSame(x, y, p); });
}

inline void expectSame(const msg::PointField& a, const msg::PointField& b, const std::string& path) {
  expectSameString(a.name, b.name, path + ".name");
  EXPECT_EQ(a.offset, b.offset) << path << ".offset";
  EXPECT_EQ(a.datatype, b.datatype) << path << ".datatype";
  EXPECT_EQ(a.count, b.count) << path << ".count";
}

inline void expectSame(const msg::PointCloud2& a, const msg::PointCloud2& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  EXPECT_EQ(a.height, b.height) << path << ".height";
  EXPECT_EQ(a.width, b.width) << path << ".width";
  expectSameSequence(a.fields, b.fields, path + ".fields",
                     [](const auto& x, const auto& y, const std::string& p) { expectSame(x, y, p); });
  EXPECT_EQ(a.is_bigendian, b.is_bigendian) << path << ".is_bigendian";
  EXPECT_EQ(a.point_step, b.point_step) << path << ".point_step";
  EXPECT_EQ(a.row_step, b.row_step) << path << ".row_step";
  ASSERT_EQ(a.data._length, b.data._length) << path << ".data._length";
  EXPECT_EQ(std::memcmp(a.data._buffer, b.data._buffer, a.data._length), 0) << path << ".data";
  EXPECT_EQ(a.is_dense, b.is_dense) << path << ".is_dense";
}

inline void expectSame(const msg::KeyValue& a, const msg::KeyValue& b, const std::string& path) {
  expectSameString(a.key, b.key, path + ".key");
  expectSameString(a.value, b.value, path + ".value");
}

inline void expectSame(const msg::DiagnosticStatus& a, const msg::DiagnosticStatus& b, const std::string& path) {
  EXPECT_EQ(a.level, b.level) << path << ".level";
  expectSameString(a.name, b.name, path + ".name");
  expectSameString(a.message, b.message, path + ".message");
  expectSameString(a.hardware_id, b.hardware_id, path + ".hardware_id");
  expectSameSequence(a.values, b.values, path + ".values",
                     [](const auto& x, const auto& y, const std::string& p) { expectSame(x, y, p); });
}

inline void expectSame(const msg::DiagnosticArray& a, const msg::DiagnosticArray& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  expectSameSequence(a.status, b.status, path + ".status",
                     [](const auto& x, const auto& y, const std::string& p) { expectSame(x, y, p); });
}

inline void expectSame(const msg::ImuState& a, const msg::ImuState& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  expectSame(a.velocity, b.velocity, path + ".velocity");
  expectSame(a.gyro_bias, b.gyro_bias, path + ".gyro_bias");
  expectSame(a.accel_bias, b.accel_bias, path + ".accel_bias");
  expectSame(a.gravity_direction, b.gravity_direction, path + ".gravity_direction");
  expectSameArray(a.velocity_covariance, b.velocity_covariance, path + ".velocity_covariance");
  expectSameArray(a.gyro_bias_covariance, b.gyro_bias_covariance, path + ".gyro_bias_covariance");
  expectSameArray(a.accel_bias_covariance, b.accel_bias_covariance, path + ".accel_bias_covariance");
  expectSameArray(a.gravity_direction_covariance, b.gravity_direction_covariance,
                  path + ".gravity_direction_covariance");
}

inline void expectSame(const msg::RingCounters& a, const msg::RingCounters& b, const std::string& path) {
  EXPECT_EQ(a.fill, b.fill) << path << ".fill";
  EXPECT_EQ(a.capacity, b.capacity) << path << ".capacity";
  EXPECT_EQ(a.overruns, b.overruns) << path << ".overruns";
}

inline void expectSame(const msg::Status& a, const msg::Status& b, const std::string& path) {
  expectSame(a.header, b.header, path + ".header");
  EXPECT_EQ(a.heartbeat, b.heartbeat) << path << ".heartbeat";
  EXPECT_EQ(a.frame_rate_hz, b.frame_rate_hz) << path << ".frame_rate_hz";
  EXPECT_EQ(a.latency_ms, b.latency_ms) << path << ".latency_ms";
  EXPECT_EQ(a.latency_p50_ms, b.latency_p50_ms) << path << ".latency_p50_ms";
  EXPECT_EQ(a.latency_p99_ms, b.latency_p99_ms) << path << ".latency_p99_ms";
  EXPECT_EQ(a.latency_max_ms, b.latency_max_ms) << path << ".latency_max_ms";
  expectSame(a.camera_ring, b.camera_ring, path + ".camera_ring");
  expectSame(a.imu_ring, b.imu_ring, path + ".imu_ring");
  expectSame(a.output_ring, b.output_ring, path + ".output_ring");
  EXPECT_EQ(a.tracking_state, b.tracking_state) << path << ".tracking_state";
  EXPECT_EQ(a.surfel_count, b.surfel_count) << path << ".surfel_count";
  EXPECT_EQ(a.frames_processed, b.frames_processed) << path << ".frames_processed";
  EXPECT_EQ(a.lost_frames, b.lost_frames) << path << ".lost_frames";
  EXPECT_EQ(a.imu_issue_frames, b.imu_issue_frames) << path << ".imu_issue_frames";
  EXPECT_EQ(a.imu_carried_frames, b.imu_carried_frames) << path << ".imu_carried_frames";
  EXPECT_EQ(a.closures_accepted, b.closures_accepted) << path << ".closures_accepted";
  EXPECT_EQ(a.closures_refused, b.closures_refused) << path << ".closures_refused";
  EXPECT_EQ(a.closures_agreed, b.closures_agreed) << path << ".closures_agreed";
  EXPECT_EQ(a.relocalisations, b.relocalisations) << path << ".relocalisations";
  EXPECT_EQ(a.frames_skipped, b.frames_skipped) << path << ".frames_skipped";
  EXPECT_EQ(a.frames_unreadable, b.frames_unreadable) << path << ".frames_unreadable";
  EXPECT_EQ(a.imu_samples_unreadable, b.imu_samples_unreadable) << path << ".imu_samples_unreadable";
  EXPECT_EQ(a.source_present, b.source_present) << path << ".source_present";
  EXPECT_EQ(a.source_reopens, b.source_reopens) << path << ".source_reopens";
  EXPECT_EQ(a.clock_offset_ns, b.clock_offset_ns) << path << ".clock_offset_ns";
  EXPECT_EQ(a.clock_skew_ppm, b.clock_skew_ppm) << path << ".clock_skew_ppm";
  EXPECT_EQ(a.sync_edge_rate_hz, b.sync_edge_rate_hz) << path << ".sync_edge_rate_hz";
  EXPECT_EQ(a.sync_edges, b.sync_edges) << path << ".sync_edges";
  EXPECT_EQ(a.map_saves, b.map_saves) << path << ".map_saves";
  EXPECT_EQ(a.map_save_failures, b.map_save_failures) << path << ".map_save_failures";
  EXPECT_EQ(a.map_save_request_done, b.map_save_request_done) << path << ".map_save_request_done";
  EXPECT_EQ(a.map_file_bytes, b.map_file_bytes) << path << ".map_file_bytes";
  EXPECT_EQ(a.map_capture_ms, b.map_capture_ms) << path << ".map_capture_ms";
  EXPECT_EQ(a.map_write_ms, b.map_write_ms) << path << ".map_write_ms";
  expectSameString(a.vifusion_version, b.vifusion_version, path + ".vifusion_version");
}

inline void expectSame(const msg::MapSaveRequest& a, const msg::MapSaveRequest& b, const std::string& path) {
  EXPECT_EQ(a.request_id, b.request_id) << path << ".request_id";
}

}  // namespace vifusion::dds::test
