#include "sample_messages.hpp"

#include <cmath>
#include <limits>

namespace vifusion::dds::test {
namespace {

SE3d samplePose(double angle_rad, double x_m) {
  return SE3d(Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(1, 2, 3).normalized())),
              Eigen::Vector3d(x_m, -2.0 / 3.0, 1e-300));
}

Matrix6d sampleCovariance(double scale) {
  Matrix6d covariance;
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < 6; ++c) covariance(r, c) = scale * (1.0 + r) / (7.0 + c);
  }
  return covariance;
}

char* text(const char* literal) { return const_cast<char*>(literal); }

}  // namespace

SampleMessages::SampleMessages() {
  const std::int64_t t_ns = 1'700'000'000'123'456'789;
  pose = makePoseStamped(t_ns, "world", samplePose(0.3, 0.1));
  odometry = makeOdometry(t_ns + 1, "world", "camera", samplePose(-2.5, 1e6), Eigen::Vector3d(0.5, -0.25, 1.0 / 3.0),
                          Eigen::Vector3d(1e-9, 3.0, -M_PI), sampleCovariance(1e-4), sampleCovariance(-7.0));

  transforms[0] = makeTransformStamped(t_ns, "world", "camera", samplePose(1.0, 2.0));
  transforms[1] = makeTransformStamped(-1, "camera", "imu", samplePose(-0.1, -3.0));
  tf = makeTfMessage(transforms);

  for (int i = 0; i < 5; ++i) {
    MapPoint p;
    p.x = 0.1f * static_cast<float>(i);
    p.y = -1.5f;
    p.z = std::numeric_limits<float>::denorm_min();
    p.rgb = MapPoint::packRgb(static_cast<std::uint8_t>(50 * i), 255, 1);
    p.normal_z = 1.0f;
    p.radius = 0.004f;
    p.confidence = static_cast<float>(i) + 0.5f;
    points.push_back(p);
  }
  map = makePointCloud2(t_ns + 2, "world", points);

  key_values[0] = {text("frames"), text("1234")};
  key_values[1] = {text("quote \" and \\ newline \n"), text("")};
  statuses[0] = {diagnostic_msgs_msg_DiagnosticStatus_Constants_WARN,
                 text("vifusion: tracking"),
                 text("lost 3 frames"),
                 text("zr300-0042"),
                 {}};
  statuses[0].values._maximum = statuses[0].values._length = 2;
  statuses[0].values._buffer = key_values.data();
  statuses[1] = {diagnostic_msgs_msg_DiagnosticStatus_Constants_STALE, text("vifusion: imu"), text(""), text(""), {}};
  diagnostics.header = makeHeader(t_ns + 3, "");
  diagnostics.status._maximum = diagnostics.status._length = 2;
  diagnostics.status._buffer = statuses.data();

  NavState x;
  x.v_I_S = Eigen::Vector3d(0.3, -0.2, 0.1);
  x.b_g = Eigen::Vector3d(1e-3, -2e-3, 3e-4);
  x.b_a = Eigen::Vector3d(0.05, 0.0, -0.07);
  x.q_I_W = Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()));
  Matrix18d covariance = Matrix18d::Identity();
  for (int i = 0; i < 18; ++i) covariance(i, i) = 1e-3 * (i + 1);
  imu_state = makeImuState(t_ns + 4, "world", x, covariance);
  Vector18d variance;
  for (int i = 0; i < 18; ++i) variance(i) = 1e-3 * (i + 1) / 3.0;
  Vector18d held = variance;
  held.segment<3>(kIdxV).setZero();
  held.segment<3>(kIdxBa).setZero();
  held.segment<3>(kIdxG).setZero();
  imu_state_from_variances = makeImuStateFromVariances(t_ns + 6, "world", x, held);
  x.r_W_C = Eigen::Vector3d(1.0 / 3.0, -1e-300, 12345.678);
  x.q_W_C = Eigen::Quaterniond(Eigen::AngleAxisd(-0.7, Eigen::Vector3d(3, -1, 2).normalized()));
  inertial_odometry = makeInertialOdometry(t_ns + 7, "world", "camera", SE3d(), x, variance,
                                           Eigen::Vector3d(0.1, -0.2, 0.3), samplePose(0.05, 0.02));

  status.header = makeHeader(t_ns + 5, "vifusion");
  status.heartbeat = std::numeric_limits<std::uint64_t>::max();
  status.frame_rate_hz = 29.97f;
  status.latency_ms = 12.5f;
  status.latency_p50_ms = 11.25f;
  status.latency_p99_ms = 31.5f;
  status.latency_max_ms = 64.0f;
  status.camera_ring = {3, 8, 17};
  status.imu_ring = {120, 1024, 0};
  status.output_ring = {1, 4, std::numeric_limits<std::uint64_t>::max() - 1};
  status.tracking_state = static_cast<std::uint8_t>(msg::TrackingState::Initialising);
  status.surfel_count = 1'999'999;
  status.frames_processed = 123'456'789'012ULL;
  status.lost_frames = 42;
  status.imu_issue_frames = 7;
  status.imu_carried_frames = 29;
  status.closures_accepted = 3;
  status.closures_refused = 41;
  status.closures_agreed = 5;
  status.relocalisations = 2;
  status.frames_skipped = 4'321;
  status.frames_unreadable = 3;
  status.imu_samples_unreadable = 7;
  status.source_present = true;
  status.source_reopens = 1;
  status.clock_offset_ns = -1'234'567'890'123;
  status.clock_skew_ppm = 12.5f;
  status.sync_edge_rate_hz = 30.0f;
  status.sync_edges = 901;
  status.map_saves = 3;
  status.map_save_failures = 1;
  status.map_save_request_done = 77;
  status.map_file_bytes = 30'812'345;
  status.map_capture_ms = 41.5f;
  status.map_write_ms = 180.25f;
  status.vifusion_version = text("0.18.0-dev");
  map_save_request.request_id = 0x0123'4567'89ab'cdefULL;
}

}  // namespace vifusion::dds::test
