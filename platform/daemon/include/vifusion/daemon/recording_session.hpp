#pragma once
// vifusiond's recording (config `record: true`): the source recorded while it is mapped, into
// <record_dir>/vifusiond-<UTC start time>.mcap (drivers/recording). The frame reader hands it every frame,
// the SLAM thread the IMU samples the frames take, the main thread the sync line's edges. A failed recording
// (disk full, storage gone) is logged once and ends; mapping goes on.

#include <cstddef>
#include <filesystem>
#include <memory>

#include "vifusion/config/daemon_config.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/recording/recorder.hpp"

namespace vifusion::daemon {

/// The recorder for `config`, or nullptr when config.record is false.
/// @throws vifusion::Error when the directory or the file cannot be created (naming it and why).
std::unique_ptr<recording::Recorder> openRecording(const config::DaemonConfig& config,
                                                   const datasets::DatasetReader& source);

/// Logs the recording's failure once (main thread); `reported` remembers that it was.
void reportRecording(const recording::Recorder& recorder, bool& reported);

/// Appends the recording's state to systemd's status line `text` (NUL-terminated, `size` bytes in all):
/// ", recording: N frames, M lost" while it runs, ", recording stopped (failed)" once it failed.
void appendRecordingStatus(const recording::Recorder& recorder, char* text, std::size_t size);

/// Stops the recording and logs what it holds.
void closeRecording(recording::Recorder& recorder);

}  // namespace vifusion::daemon
