#include "vifusion/config/daemon_config.hpp"

#include <cmath>

namespace vifusion::config {
namespace {

void require(bool ok, const std::string& message) {
  if (!ok) throw ConfigError(message);
}

bool positiveFinite(double value) { return std::isfinite(value) && value > 0.0; }

}  // namespace

void DaemonConfig::validate() const {
  require(
      !source.empty(),
      "key 'source' is empty: give sim:NAME, dataset:DIR, tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE or zr300[:SERIAL]");
  require(!out.empty(), "key 'out' is empty: give the state directory for trajectory.txt and map.ply");
  require(mode == "rgbd" || mode == "rgbdi" || mode == "gyro",
          "key 'mode' = '" + mode + "' is unknown: rgbd, rgbdi or gyro");
  require(sync.edges == "rising" || sync.edges == "falling" || sync.edges == "both",
          "key 'sync.edges' = '" + sync.edges + "' is unknown: rising, falling or both");
  require(sync.line >= 0 && sync.line <= 65535,
          "key 'sync.line' = " + std::to_string(sync.line) + " is outside [0, 65535]");
  require(max_frames >= 0, "key 'max_frames' = " + std::to_string(max_frames) + " must be >= 0 (0: the whole source)");
  require(replay_loops >= 1 && replay_loops <= kMaxReplayLoops,
          "key 'replay_loops' = " + std::to_string(replay_loops) + " must be in 1.." + std::to_string(kMaxReplayLoops));
  require(frame_ring >= 1 && frame_ring <= 64,
          "key 'frame_ring' = " + std::to_string(frame_ring) + " must be in 1..64");
  require(map_capacity >= (1 << 16) && map_capacity <= (1 << 26),
          "key 'map_capacity' = " + std::to_string(map_capacity) + " must be in 65536..67108864 surfels");
  require(std::isfinite(map_publish_period_s) && map_publish_period_s >= 0.0,
          "key 'map_publish_period_s' must be >= 0 (0: never)");
  require(std::isfinite(map_save_period_s) && map_save_period_s >= 0.0,
          "key 'map_save_period_s' must be >= 0 (0: save on stop and on request only)");
  require(mapping || (!map_file.empty() && map_file_required),
          "key 'mapping' is false (localisation only), which tracks against a saved map: give it with 'map_file' and "
          "keep 'map_file_required' true");
  require(positiveFinite(status_period_s) && status_period_s <= 1.0,
          "key 'status_period_s' must be in (0, 1] s: health needs the status at >= 1 Hz");
  require(dds.domain <= 232, "key 'dds.domain' = " + std::to_string(dds.domain) + " must be in 0..232");
  require(!dds.config.empty(), "key 'dds.config' is empty: give the Cyclone DDS XML (file or inline)");
  require(dds.partition.find_first_of("*?[]") == std::string::npos, "key 'dds.partition' must not contain * ? [ ]");
  require(!dds.world_frame.empty() && !dds.odom_frame.empty() && !dds.camera_frame.empty() &&
              dds.world_frame != dds.odom_frame && dds.world_frame != dds.camera_frame &&
              dds.odom_frame != dds.camera_frame,
          "keys 'dds.world_frame', 'dds.odom_frame' and 'dds.camera_frame' must be non-empty and different");
  require(positiveFinite(health.period_s) && health.period_s <= 1.0, "key 'health.period_s' must be in (0, 1] s");
  require(positiveFinite(health.heartbeat_stale_s) && health.heartbeat_stale_s >= status_period_s,
          "key 'health.heartbeat_stale_s' must be > 0 and >= status_period_s");
  require(std::isfinite(health.min_frame_rate_hz) && health.min_frame_rate_hz >= 0.0,
          "key 'health.min_frame_rate_hz' must be >= 0");
  require(std::isfinite(health.lost_error_s) && health.lost_error_s >= 0.0, "key 'health.lost_error_s' must be >= 0");
  require(health.led_line >= 0, "key 'health.led_line' must be >= 0");
}

}  // namespace vifusion::config
