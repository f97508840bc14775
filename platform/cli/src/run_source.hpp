#pragma once
// The source of `vifusion run`, `record` and `synccheck`: a recorded one (a dataset spec, `rec:FILE.mcap`,
// `sim:NAME`, generated into <out>/sim_NAME on first use) or the live camera `zr300[:SERIAL]`, with the IMU
// feed each frame's samples come from. A live source runs until Ctrl-C or SIGTERM once
// watchInterrupts() was called.

#include <cstddef>
#include <memory>
#include <string>

#include "vifusion/core/imu_feed.hpp"
#include "vifusion/datasets/dataset_reader.hpp"
#include "vifusion/datasets/fault_injection.hpp"

namespace vifusion::zr300 {
class Zr300Backend;
class Zr300Source;
}  // namespace vifusion::zr300

namespace vifusion::cli {

/// Poses reserved up front for a live run without --frames: an hour at 30 Hz; longer runs grow the vector.
inline constexpr std::size_t kLiveReservedFrames = 108'000;

struct SourceRequest {
  std::string spec;  ///< sim:NAME, tum:DIR, icl:DIR, 7scenes:DIR, klg:FILE, dataset:DIR, rec:FILE, zr300[:SERIAL]
  /// The rig's calibration.yaml (kalibr.hpp's schema): zr300 reads it; a recorded source is read with it in
  /// place of its own (datasets::withCalibration). Empty: the recording's own.
  std::string calibration;
  std::string out;        ///< where a sim:NAME sequence is generated (<out>/sim_NAME)
  bool inertial = false;  ///< the IMU is needed (zr300: the motion module is opened only then)
  /// zr300: keep the motion module's transfers as received (Zr300Source::rawTransferRing()), this many at most.
  std::size_t raw_transfers = 0;
  /// Faults to replay a recorded source with (datasets::withFaults); the live camera takes none.
  datasets::FaultPlan faults;
  /// A recorded source read through datasets::withIncreasingTimes (run: a frame or IMU sample out of time order is
  /// skipped and counted). false for record and synccheck, which pass on or judge the timestamps as they are.
  bool time_order_guard = false;
};

/// A source's frames and their IMU samples: a recording hands every frame its whole IMU stream, the live
/// camera a window of its driver's ring.
struct RunSource {
  std::unique_ptr<datasets::DatasetReader> reader;
  std::unique_ptr<RecordedImuFeed> recorded_imu;
  ImuFeed* imu = nullptr;                ///< null: the source has no IMU
  zr300::Zr300Source* camera = nullptr;  ///< the live camera, when the source is one
};

/// Opens the source, or returns false after printing "<command>: cannot open source …" when the live camera
/// cannot be opened (exit code 3). `backend` reaches the camera (null: the real devices).
/// @throws vifusion::Error for a bad recorded source.
bool openRunSource(const SourceRequest& request, const char* command, std::unique_ptr<zr300::Zr300Backend> backend,
                   RunSource& source);

/// From now until forgetSource(): SIGINT and SIGTERM end a live source's nextFrame() and set interrupted().
void watchInterrupts(RunSource& source);
bool interrupted();
/// Stops the signal handlers from reaching the source (before it is destroyed).
void forgetSource();

}  // namespace vifusion::cli
