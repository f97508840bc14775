#include "vifusion/config/config_keys.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <type_traits>

namespace vifusion::config {

std::vector<ConfigKey> configKeys(DaemonConfig& c) {
  return {
      {"source", "sim:NAME, dataset:DIR, tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE or the live camera zr300[:SERIAL]",
       &c.source},
      {"calibration",
       "The rig's calibration.yaml (Kalibr cam0/imu0 keys). zr300: its image size picks the stream; a recorded "
       "source is read with it in place of its own",
       &c.calibration},
      {"out", "State directory: trajectory.txt, map.ply (written atomically), generated sim data", &c.out},
      {"mode", "rgbd, rgbdi (camera + IMU, needs a source with IMU data) or gyro (camera + gyroscope)", &c.mode},
      {"max_frames", "Stop cleanly after this many frames (0: whole source)", &c.max_frames},
      {"realtime", "Replay a dataset at its timestamps (false: as fast as possible)", &c.realtime},
      {"device", "GPU name filter (\"\": best device)", &c.device},
      {"frame_ring", "Camera ring capacity [frames]", &c.frame_ring},
      {"map_capacity", "Surfels the map holds (fixed GPU memory, about 110 bytes a surfel)", &c.map_capacity},
      {"map_publish_period_s", "Publish rt/vifusion/map every this many seconds (0: never)", &c.map_publish_period_s},
      {"status_period_s", "Publish rt/vifusion/status every this many seconds", &c.status_period_s},
      {"map_file", "Map file loaded at start and saved on stop, periodically and on request (\"\": none)", &c.map_file},
      {"map_file_required", "A missing or refused map_file stops the start (false: start with an empty map)",
       &c.map_file_required},
      {"map_save_period_s", "Save map_file every this many seconds while running (0: on stop and request only)",
       &c.map_save_period_s},
      {"mapping", "false: localisation only, track against map_file without changing it (needs map_file)", &c.mapping},
      {"log_file", "Log file, reopened on SIGHUP (\"\": stderr)", &c.log_file},
      {"record", "Record the source while mapping (frames, IMU, sync edges; MCAP, ROS 2 messages)", &c.record},
      {"record_dir", "Directory of the recordings (\"\": <out>/recordings); one vifusiond-TIME.mcap per start",
       &c.record_dir},
      {"inject",
       "Replay a recorded source with faults, NAME@FRAME[:VALUE],... e.g. device-lost@300 (tests; README \"Bad input "
       "and faults\")",
       &c.inject},
      {"replay_loops",
       "Replay a recorded source this many times end to end, each pass later by its span (soak runs; 1: once)",
       &c.replay_loops},
      {"dds.domain", "DDS domain id (0..232)", &c.dds.domain},
      {"dds.config", "Cyclone DDS XML: file, file:// URI or inline", &c.dds.config},
      {"dds.partition", "DDS partition (\"\": default, as ROS 2)", &c.dds.partition},
      {"dds.world_frame", "frame_id of the map world", &c.dds.world_frame},
      {"dds.odom_frame", "frame_id of the odometry frame (REP-105: map -> odom -> camera)", &c.dds.odom_frame},
      {"dds.camera_frame", "frame_id of the camera", &c.dds.camera_frame},
      {"health.period_s", "vifusion-health: judge and publish rt/diagnostics every [s]", &c.health.period_s},
      {"health.heartbeat_stale_s", "vifusion-health: status older than this is STALE [s]", &c.health.heartbeat_stale_s},
      {"health.min_frame_rate_hz", "vifusion-health: frame rate below this is WARN [Hz]", &c.health.min_frame_rate_hz},
      {"health.lost_error_s", "vifusion-health: tracking lost longer than this is ERROR [s]", &c.health.lost_error_s},
      {"health.led_chip", "vifusion-health: status LED gpiochip (\"\": no LED)", &c.health.led_chip},
      {"health.led_line", "vifusion-health: status LED line offset", &c.health.led_line},
      {"sync.chip", "Sync line (camera strobe, external trigger): gpiochip name or path (\"\": none)", &c.sync.chip},
      {"sync.line", "Sync line: line offset on sync.chip", &c.sync.line},
      {"sync.edges", "Sync line: rising, falling or both", &c.sync.edges},
  };
}

const char* typeName(const ConfigKey& key) {
  return std::visit(
      [](auto* field) -> const char* {
        using T = std::remove_pointer_t<decltype(field)>;
        if constexpr (std::is_same_v<T, std::string>) return "a string";
        if constexpr (std::is_same_v<T, bool>) return "true or false";
        if constexpr (std::is_same_v<T, double>) return "a number";
        if constexpr (std::is_same_v<T, std::uint32_t>) return "a non-negative integer";
        return "an integer";
      },
      key.field);
}

namespace {

constexpr unsigned char kFirstPrintable = 0x20;  ///< ASCII space; bytes below it are control characters
constexpr unsigned char kDelete = 0x7f;

std::string quoted(const std::string& text) {
  // Quote whatever YAML could read as something else (empty, numbers, booleans, special characters).
  const bool plain = !text.empty() && text.find_first_of(":#{}[],&*!|>'\"%@`\n") == std::string::npos &&
                     text.front() != ' ' && text.back() != ' ' && text.front() != '-' && text != "true" &&
                     text != "false" && text != "yes" && text != "no" && text != "null" && text != "~" &&
                     !(std::isdigit(static_cast<unsigned char>(text.front())));
  if (plain) return text;
  std::string out = "\"";
  for (char ch : text) {
    if (ch == '"' || ch == '\\') out += '\\';
    out += ch;
  }
  return out + "\"";
}

template <typename Int>
bool parseInt(std::string_view text, Int& out) {
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end && !text.empty();
}

}  // namespace

std::string formatValue(const ConfigKey& key) {
  return std::visit(
      [](auto* field) -> std::string {
        using T = std::remove_pointer_t<decltype(field)>;
        if constexpr (std::is_same_v<T, std::string>) {
          return quoted(*field);
        } else if constexpr (std::is_same_v<T, bool>) {
          return *field ? "true" : "false";
        } else if constexpr (std::is_same_v<T, double>) {
          char text[32] = {};
          // Shortest text that reads back exactly.
          for (int digits = 1; digits <= 17; ++digits) {
            std::snprintf(text, sizeof(text), "%.*g", digits, *field);
            if (std::strtod(text, nullptr) == *field) break;
          }
          return text;
        } else {
          return std::to_string(*field);
        }
      },
      key.field);
}

void parseValue(const ConfigKey& key, std::string_view text, std::string_view where) {
  const auto fail = [&] {
    throw ConfigError(std::string(where) + "key '" + key.path + "' must be " + typeName(key) + ", got '" +
                      std::string(text) + "'");
  };
  std::visit(
      [&](auto* field) {
        using T = std::remove_pointer_t<decltype(field)>;
        if constexpr (std::is_same_v<T, std::string>) {
          // Sources, paths, frame ids and partitions are one line of text; a control character (a NUL or a
          // line break from a corrupted file) would reach a file name or the wire unseen.
          const auto control = std::find_if(text.begin(), text.end(),
                                            [](unsigned char c) { return c < kFirstPrintable || c == kDelete; });
          if (control != text.end()) {
            char code[8];
            std::snprintf(code, sizeof(code), "0x%02x", static_cast<unsigned char>(*control));
            throw ConfigError(std::string(where) + "key '" + key.path + "' holds a control character (" + code +
                              " at offset " + std::to_string(control - text.begin()) +
                              "); its value must be one line of printable text");
          }
          *field = std::string(text);
        } else if constexpr (std::is_same_v<T, bool>) {
          if (text == "true" || text == "yes" || text == "on" || text == "1") {
            *field = true;
          } else if (text == "false" || text == "no" || text == "off" || text == "0") {
            *field = false;
          } else {
            fail();
          }
        } else if constexpr (std::is_same_v<T, double>) {
          const std::string copy(text);
          char* end = nullptr;
          errno = 0;
          const double value = std::strtod(copy.c_str(), &end);
          if (copy.empty() || end != copy.c_str() + copy.size() || errno != 0 || !std::isfinite(value)) fail();
          *field = value;
        } else {
          if (!parseInt(text, *field)) fail();
        }
      },
      key.field);
}

std::string dumpYaml(DaemonConfig& config) {
  std::string out = "# vifusiond effective configuration\n";
  std::string section;
  for (const ConfigKey& key : configKeys(config)) {
    const std::size_t dot = key.path.find('.');
    const std::string key_section = dot == std::string::npos ? "" : key.path.substr(0, dot);
    if (key_section != section) {
      section = key_section;
      if (!section.empty()) out += section + ":\n";
    }
    const std::string name = dot == std::string::npos ? key.path : key.path.substr(dot + 1);
    out += (section.empty() ? "" : "  ") + name + ": " + formatValue(key) + "\n";
  }
  return out;
}

std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates) {
  std::string best;
  std::size_t best_distance = std::numeric_limits<std::size_t>::max();
  for (const std::string& candidate : candidates) {
    // Levenshtein distance, two rows.
    std::vector<std::size_t> previous(candidate.size() + 1), current(candidate.size() + 1);
    for (std::size_t j = 0; j <= candidate.size(); ++j) previous[j] = j;
    for (std::size_t i = 1; i <= word.size(); ++i) {
      current[0] = i;
      for (std::size_t j = 1; j <= candidate.size(); ++j) {
        const std::size_t substitute = previous[j - 1] + (word[i - 1] == candidate[j - 1] ? 0 : 1);
        current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitute});
      }
      std::swap(previous, current);
    }
    if (previous[candidate.size()] < best_distance) {
      best_distance = previous[candidate.size()];
      best = candidate;
    }
  }
  // A typo: at most a third of the word, and at least one edit allowed.
  const std::size_t allowed = std::max<std::size_t>(1, word.size() / 3);
  return best_distance <= allowed ? best : std::string();
}

}  // namespace vifusion::config
