#include "service_commands.hpp"

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <memory>
#include <string>

#include "vifusion/config/yaml_loader.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/echo.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"

namespace vifusion::cli {
namespace {

constexpr const char* kSystemConfig = "/etc/vifusion/vifusiond.yaml";

dds::ParticipantOptions participantOptions(const DdsSelection& selection) {
  config::DaemonConfig daemon;
  if (!selection.config_file.empty()) {
    config::loadYamlFile(selection.config_file, daemon);
  } else if (std::filesystem::exists(kSystemConfig)) {
    config::loadYamlFile(kSystemConfig, daemon);
  }
  dds::ParticipantOptions options{daemon.dds.domain, daemon.dds.config, daemon.dds.partition};
  if (!selection.dds_config.empty()) options.config = selection.dds_config;
  if (selection.domain >= 0) options.domain_id = static_cast<std::uint32_t>(selection.domain);
  if (!selection.partition.empty()) options.partition = selection.partition;
  return options;
}

const char* levelName(std::uint8_t level) {
  switch (level) {
    case 0:
      return "OK";
    case 1:
      return "WARN";
    case 2:
      return "ERROR";
    case 3:
      return "STALE";
  }
  return "?";
}

const char* trackingName(std::uint8_t state) {
  switch (static_cast<dds::msg::TrackingState>(state)) {
    case dds::msg::TrackingState::Ok:
      return "tracking";
    case dds::msg::TrackingState::Lost:
      return "LOST";
    case dds::msg::TrackingState::Initialising:
      return "initialising";
    case dds::msg::TrackingState::ImuCarried:
      return "IMU-carried";
    case dds::msg::TrackingState::Relocalising:
      return "relocalising into the loaded map";
  }
  return "?";
}

}  // namespace

int runEcho(const EchoCommandOptions& options) {
  dds::EchoOptions echo;
  try {
    echo.participant = participantOptions(options.dds);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "vifusion echo: %s\n", error.what());
    return dds::kEchoFailed;
  }
  echo.topic = options.topic;
  echo.count = options.count;
  echo.timeout_ns = secondsToNs(options.timeout_s);
  echo.full_arrays = options.full_arrays;
  return dds::echo(echo, stdout);
}

int runStatus(const StatusCommandOptions& options) {
  const dds::Participant participant(participantOptions(options.dds));
  dds::Reader<dds::msg::Status> status_reader(participant, dds::topics::kStatus);
  dds::Reader<dds::msg::DiagnosticArray> diagnostics_reader(participant, dds::topics::kDiagnostics);
  const std::int64_t deadline_ns = monotonicNowNs() + secondsToNs(options.timeout_s);
  bool have_status = false, have_diagnostics = false, all_ok = true;
  std::string status_text, diagnostics_text;
  while ((!have_status || !have_diagnostics) && monotonicNowNs() < deadline_ns) {
    const std::int64_t left_ns = std::max<std::int64_t>(0, deadline_ns - monotonicNowNs());
    status_reader.waitForData(std::min<std::int64_t>(left_ns, 50 * kNsPerMillisecond));
    if (!have_status) {
      status_reader.take(
          [&](const dds::msg::Status& s) {
            char line[512];
            std::snprintf(
                line, sizeof(line),
                "vifusiond: %s, %.1f frames/s, latency %.0f ms (p50 %.0f, p99 %.0f, max %.0f), %llu frames (%llu "
                "skipped "
                "as stale, %llu unreadable, %llu lost, "
                "%llu IMU-carried, "
                "%llu without usable IMU), %u surfels, %llu loop closures (%llu agreed, %llu refused), %llu "
                "relocalisations, camera ring %u/%u "
                "(%llu overruns), heartbeat %llu\n",
                trackingName(s.tracking_state), static_cast<double>(s.frame_rate_hz), static_cast<double>(s.latency_ms),
                static_cast<double>(s.latency_p50_ms), static_cast<double>(s.latency_p99_ms),
                static_cast<double>(s.latency_max_ms), static_cast<unsigned long long>(s.frames_processed),
                static_cast<unsigned long long>(s.frames_skipped), static_cast<unsigned long long>(s.frames_unreadable),
                static_cast<unsigned long long>(s.lost_frames), static_cast<unsigned long long>(s.imu_carried_frames),
                static_cast<unsigned long long>(s.imu_issue_frames), s.surfel_count,
                static_cast<unsigned long long>(s.closures_accepted),
                static_cast<unsigned long long>(s.closures_agreed), static_cast<unsigned long long>(s.closures_refused),
                static_cast<unsigned long long>(s.relocalisations), s.camera_ring.fill, s.camera_ring.capacity,
                static_cast<unsigned long long>(s.camera_ring.overruns), static_cast<unsigned long long>(s.heartbeat));
            status_text = line;
            if (s.imu_samples_unreadable > 0) {
              std::snprintf(line, sizeof(line), "vifusiond: %llu recorded IMU samples unreadable, left out (logged)\n",
                            static_cast<unsigned long long>(s.imu_samples_unreadable));
              status_text += line;
            }
            if (!s.source_present) status_text += "vifusiond: camera absent (unplugged): the map is kept\n";
            if (s.clock_offset_ns != 0 || s.source_reopens > 0) {
              std::snprintf(line, sizeof(line),
                            "vifusiond: live camera: IMU clock offset %.6f s, skew %.2f ppm, IMU ring %u/%u (%llu "
                            "overruns), re-opened %llu times\n",
                            static_cast<double>(s.clock_offset_ns) * 1e-9, static_cast<double>(s.clock_skew_ppm),
                            s.imu_ring.fill, s.imu_ring.capacity, static_cast<unsigned long long>(s.imu_ring.overruns),
                            static_cast<unsigned long long>(s.source_reopens));
              status_text += line;
            }
            if (s.map_saves > 0 || s.map_save_failures > 0) {
              std::snprintf(line, sizeof(line),
                            "vifusiond: map file: %llu saves (%llu failed), last %llu bytes (SLAM thread held %.0f ms, "
                            "written in %.0f ms)\n",
                            static_cast<unsigned long long>(s.map_saves),
                            static_cast<unsigned long long>(s.map_save_failures),
                            static_cast<unsigned long long>(s.map_file_bytes), static_cast<double>(s.map_capture_ms),
                            static_cast<double>(s.map_write_ms));
              status_text += line;
            }
            if (s.sync_edges > 0 || s.sync_edge_rate_hz > 0.0f) {
              std::snprintf(line, sizeof(line), "vifusiond: sync line: %.1f edges/s, %llu edges\n",
                            static_cast<double>(s.sync_edge_rate_hz), static_cast<unsigned long long>(s.sync_edges));
              status_text += line;
            }
            have_status = true;
          },
          1);
    }
    if (!have_diagnostics) {
      diagnostics_reader.take(
          [&](const dds::msg::DiagnosticArray& array) {
            diagnostics_text.clear();
            all_ok = true;
            for (std::uint32_t i = 0; i < array.status._length; ++i) {
              const dds::msg::DiagnosticStatus& s = array.status._buffer[i];
              all_ok = all_ok && s.level == 0;
              diagnostics_text += std::string("  ") + levelName(s.level) + "  " + s.name + ": " + s.message + "\n";
            }
            have_diagnostics = true;
          },
          1);
    }
  }
  std::fputs(have_status ? status_text.c_str()
                         : "vifusiond: no rt/vifusion/status received (not running, or "
                           "another DDS domain/partition?)\n",
             stdout);
  if (have_diagnostics) {
    std::printf("health: %s\n%s", all_ok ? "OK" : "NOT OK", diagnostics_text.c_str());
  } else {
    std::printf("health: no rt/diagnostics received (is vifusion-health running?)\n");
  }
  return have_status && have_diagnostics && all_ok ? 0 : 1;
}

int runMapSave(const MapSaveCommandOptions& options) {
  std::unique_ptr<dds::Participant> participant;
  try {
    participant = std::make_unique<dds::Participant>(participantOptions(options.dds));
  } catch (const std::exception& error) {
    std::fprintf(stderr, "vifusion map save: %s\n", error.what());
    return 2;
  }
  dds::Reader<dds::msg::Status> status_reader(*participant, dds::topics::kStatus);
  dds::Writer<dds::msg::MapSaveRequest> request_writer(*participant, dds::topics::kMapSaveRequest);
  const std::int64_t deadline_ns = monotonicNowNs() + secondsToNs(options.timeout_s);
  constexpr std::int64_t kPollNs = 50 * kNsPerMillisecond;

  // The service's request reader must have matched, or the request (volatile) reaches nobody; and its last
  // counts before the request tell afterwards whether this save succeeded.
  bool have_status = false;
  dds::msg::Status before{};
  while ((!have_status || request_writer.matchedReaders() == 0) && monotonicNowNs() < deadline_ns) {
    status_reader.waitForData(kPollNs);
    status_reader.take([&](const dds::msg::Status& s) {
      before = s;
      have_status = true;
    });
  }
  if (!have_status || request_writer.matchedReaders() == 0) {
    std::printf("vifusion map save: no vifusiond found within %.0f s (not running, or another DDS domain/partition?)\n",
                options.timeout_s);
    return 1;
  }
  // Ids grow across requesters and runs: the wall clock in ns (the service keeps the largest it has seen).
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  const std::uint64_t request_id =
      static_cast<std::uint64_t>(now.tv_sec) * 1'000'000'000ULL + static_cast<std::uint64_t>(now.tv_nsec);
  request_writer.write(dds::msg::MapSaveRequest{request_id});

  while (monotonicNowNs() < deadline_ns) {
    status_reader.waitForData(kPollNs);
    bool answered = false;
    dds::msg::Status after{};
    status_reader.take([&](const dds::msg::Status& s) {
      if (s.map_save_request_done >= request_id && !answered) {
        after = s;
        answered = true;
      }
    });
    if (!answered) continue;
    if (after.map_saves > before.map_saves) {
      std::printf(
          "vifusion map save: saved, %llu bytes (SLAM thread held %.0f ms for the readback, written in %.0f "
          "ms)\n",
          static_cast<unsigned long long>(after.map_file_bytes), static_cast<double>(after.map_capture_ms),
          static_cast<double>(after.map_write_ms));
      return 0;
    }
    if (after.map_save_failures > before.map_save_failures) {
      std::printf("vifusion map save: the save failed and the map file is unchanged (vifusiond's log says why)\n");
    } else if (after.tracking_state == static_cast<std::uint8_t>(dds::msg::TrackingState::Relocalising)) {
      std::printf(
          "vifusion map save: not saved: vifusiond is still relocalising into the map it loaded, which is "
          "the file as it is\n");
    } else {
      std::printf(
          "vifusion map save: not saved: vifusiond has no map_file configured, or runs localisation only "
          "(mapping: false), which never changes it\n");
    }
    return 1;
  }
  std::printf("vifusion map save: no answer from vifusiond within %.0f s\n", options.timeout_s);
  return 1;
}

}  // namespace vifusion::cli
