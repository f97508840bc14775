#pragma once
// Where `vifusion sim` writes a generated sequence: a dataset directory (DatasetWriter, TUM layout) or a
// recording (an MCAP file, RecordingSequenceWriter). Both take the same calls in the same order.

#include <cstdint>
#include <span>

#include "vifusion/core/image.hpp"
#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::cli {

class SequenceWriter {
 public:
  virtual ~SequenceWriter() = default;
  /// The rig; first, before any data.
  virtual void writeCalibration(const RigCalibration& calibration) = 0;
  /// Every IMU sample and ground-truth state of the sequence, in time order; before the frames.
  virtual void writeImu(std::span<const ImuSample> samples) = 0;
  virtual void writeGroundTruthStates(std::span<const GroundTruthState> states) = 0;
  /// One frame's images; T_W_C is the true camera pose at t_ns. Frames in time order.
  virtual void writeFrame(std::int64_t t_ns, ImageView<const Rgb8> rgb, ImageView<const std::uint16_t> depth,
                          const SE3d& T_W_C) = 0;
  /// Completes the output (indices renamed, summary written); nothing is complete before.
  virtual void finish() = 0;
};

}  // namespace vifusion::cli
