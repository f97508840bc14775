#pragma once
// A recording replayed end to end several times as one long source (vifusiond's `replay_loops`): the way to run the
// service for hours on a recording of a minute (issue 22's 10 000-frame soak). Pass p delivers the recording's frames
// and IMU samples p × (its span + one frame period) later, so time keeps increasing across the seam; the camera
// jumps there from the last pose back to the first, as a robot carried back to its start would (tracking finds the
// mapped place again by relocalisation).

#include <cstddef>
#include <functional>
#include <memory>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets {

/// Opens the recording afresh (each pass reads it from its start).
using RecordingOpener = std::function<std::unique_ptr<DatasetReader>()>;

/// `passes` replays of what `open` opens (≥ 1; 1 is the recording itself). The IMU stream of all passes is built
/// once here (passes × the recording's samples); each later pass rewinds the recording (DatasetReader::rewind) or,
/// where it cannot, reopens it at its first frame.
/// @throws vifusion::Error naming the recording when passes < 1, or it is live, has fewer than 2 frames or lists
/// no frame times (its span is needed before the first pass ends).
std::unique_ptr<DatasetReader> loopedReplay(const RecordingOpener& open, std::size_t passes);

}  // namespace vifusion::datasets
