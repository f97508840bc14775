#pragma once
// The reader thread: decodes frames from the source into the camera ring.

#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/recording/recorder.hpp"

namespace vifusion::daemon {

/// Runs until the source ends, `state.stop` is set or the source fails (exit code 3). A recorded frame that
/// cannot be read (a truncated image, a damaged message) is passed over: counted in
/// SharedState::frames_unreadable (the status message) and logged with the reader's reason, which names the
/// file; the next frame is read. An error from a live source is final (its driver recovers what it can).
///  realtime = true: frames are handed over at their timestamps' pace, like a camera; a full ring
///    drops the newest frame and counts an overrun (a sensor never waits); the SLAM thread takes the newest
///    waiting frame and skips the older ones (SlamWorkerOptions::take_newest).
///  realtime = false: as fast as the SLAM thread takes them; the reader waits for a free slot,
///    because a dataset replayed for evaluation should lose nothing.
///  A live source (the camera) is never paced: frames are handed over as they come; with realtime = true a
///  full ring drops the newest, with false the reader waits (the camera's driver then drops, counted).
///  recorder (optional): every frame read is also handed to it (a copy into its ring; never waits).
void runFrameReader(datasets::DatasetReader& source, bool realtime, SharedState& state,
                    recording::Recorder* recorder = nullptr);

}  // namespace vifusion::daemon
