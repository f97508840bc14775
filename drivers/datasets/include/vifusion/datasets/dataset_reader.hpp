#pragma once
// One interface over every recorded RGB-D(-inertial) dataset: TUM RGB-D, ICL-NUIM, 7-Scenes,
// ElasticFusion .klg logs and our own dataset directories (written by `vifusion sim`, DESIGN §5).
// A reader validates the whole index (timestamps, columns, referenced files) when it is opened and
// decodes images lazily in nextFrame(); every problem is a vifusion::Error naming the file, the line
// or frame and what is wrong, never a crash.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include "vifusion/core/rig_calibration.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"

namespace vifusion::datasets {

/// A ground-truth pose. For every reader here the body is the camera C, so this is T_world_camera
/// (p_world = T_world_body · p_C) in the dataset's own world frame.
struct StampedPose {
  std::int64_t t_ns = 0;  ///< stamp [ns] on the dataset's time base (the frames' base)
  SE3d T_world_body;
};

class DatasetReader {
 public:
  virtual ~DatasetReader() = default;

  /// Intrinsics, depth units, extrinsics and IMU noise of the data (defaults where the dataset has
  /// none; describe() says which).
  virtual const RigCalibration& calibration() const = 0;

  /// Number of frames nextFrame() will deliver in total; 0 for a live source, which cannot know.
  virtual std::size_t frameCount() const = 0;

  /// A camera rather than a recording: frames come at the sensor's pace, nextFrame() waits for them, and
  /// the IMU comes through an ImuFeed over the driver's ring instead of imu().
  virtual bool live() const { return false; }

  /// Decodes the next frame into `frame`, reusing its image buffers when the size is unchanged.
  /// @return false once every frame has been delivered (frame is then untouched).
  /// @throws vifusion::Error for an unreadable, truncated or wrongly sized/typed image, naming it; a recorded
  /// source has then moved past that frame, so the next call reads the one after (a caller may skip it).
  virtual bool nextFrame(RgbdFrame& frame) = 0;

  /// Goes back to the first frame, so that nextFrame() delivers the sequence again, keeping everything already
  /// read (the lists, the IMU, the ground truth): a looped replay then allocates nothing at its seams.
  /// @return false where the source cannot (live sources, recordings read as a stream); open it afresh instead.
  virtual bool rewind() { return false; }

  /// The time a recorded source lists for its frame `index` (0-based, in nextFrame() order), known even when
  /// the frame cannot be read; nullopt where the source lists none (live sources, recordings).
  virtual std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const {
    (void)index;
    return std::nullopt;
  }

  /// Every IMU sample of the sequence, strictly increasing in time; empty if the dataset has none.
  virtual std::span<const ImuSample> imu() const { return {}; }

  /// IMU rows that could not be read (not a number, a column missing, time not increasing) and were left
  /// out of imu(), each as the reader's error naming file and line; the estimator sees the hole as a gap.
  virtual std::span<const std::string> skippedImuRows() const { return {}; }

  /// Ground-truth camera poses T_world_camera, strictly increasing in time; empty if none.
  virtual std::span<const StampedPose> groundTruth() const { return {}; }

  /// Full ground-truth states of S (our simulator's datasets only); empty otherwise.
  virtual std::span<const GroundTruthState> groundTruthStates() const { return {}; }

  /// One line for logs and reports: format, path, frame count, what calibration was assumed.
  virtual std::string describe() const = 0;
};

/// Opens a dataset from a source spec (DESIGN §5):
///   tum:DIR      TUM RGB-D sequence folder (rgb.txt, depth.txt, optional accelerometer.txt, groundtruth.txt)
///   icl:DIR      ICL-NUIM TUM-compatible folder (associations.txt, rgb/, depth/, optional *.gt.freiburg)
///   7scenes:DIR  7-Scenes sequence (frame-XXXXXX.{color,depth}.png, .pose.txt), directly or under rgbd-frames/
///   klg:FILE     ElasticFusion .klg log
///   dataset:DIR  our own dataset directory (TUM layout + imu.csv + calibration.yaml + ground truth)
/// `sim:NAME` presets, `rec:FILE` and `zr300` belong to the vifusion CLI, which generates or opens the
/// source itself; here they are rejected with a message saying so.
/// @throws vifusion::Error for an unknown prefix (listing the valid ones) or an invalid dataset.
std::unique_ptr<DatasetReader> openDataset(const std::string& spec);

}  // namespace vifusion::datasets
