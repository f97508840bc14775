#include <algorithm>
#include <limits>
#include <thread>
#include <utility>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/datasets/fault_injection.hpp"

namespace vifusion::datasets {
namespace {

/// What happens to one IMU sample of the recording on its way out.
struct SampleFaults {
  bool removed = false;
  bool repeated = false;
  bool swapped_with_next = false;
  bool nan_accel = false;
  bool inf_gyro = false;
};

class FaultInjectingReader final : public DatasetReader {
 public:
  FaultInjectingReader(std::unique_ptr<DatasetReader> recording, const FaultPlan& plan)
      : recording_(std::move(recording)), plan_(plan) {
    if (recording_->live()) throw Error(recording_->describe() + ": faults are injected into recordings only");
    const std::size_t frames = recording_->frameCount();
    for (const Fault& fault : plan.faults) {
      if (fault.frame >= frames) {
        throw Error("fault injection into " + recording_->describe() + ": '" + FaultPlan{{fault}}.describe() +
                    "' is at frame " + std::to_string(fault.frame) + " but the source has " + std::to_string(frames) +
                    " frames (0 to " + std::to_string(frames - 1) + ")");
      }
    }
    planFrames(frames);
    planImu();
  }

  const RigCalibration& calibration() const override { return recording_->calibration(); }
  std::size_t frameCount() const override { return deliveries_.size(); }

  bool nextFrame(RgbdFrame& frame) override {
    if (next_ >= deliveries_.size()) return false;
    const Delivery delivery = deliveries_[next_++];
    if (delivery.stall_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(delivery.stall_ns));
    if (delivery.repeat) {
      frame = repeated_;
      return true;
    }
    while (source_position_ < delivery.source) {  // the dropped frames: read, never shown, their errors too
      ++source_position_;
      try {
        recording_->nextFrame(dropped_);
      } catch (const Error&) {
      }
    }
    ++source_position_;
    if (!recording_->nextFrame(frame)) return false;
    frame.t_ns += delivery.shift_ns;
    if (delivery.blank) {
      std::fill_n(frame.depth.data(), frame.depth.pixelCount(), std::uint16_t{0});
      std::fill_n(frame.rgb.data(), frame.rgb.pixelCount(), Rgb8{});
    }
    if (next_ < deliveries_.size() && deliveries_[next_].repeat) repeated_ = frame;
    return true;
  }

  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override {
    if (index >= deliveries_.size()) return std::nullopt;
    const std::optional<std::int64_t> listed = recording_->listedFrameTimeNs(deliveries_[index].source);
    if (!listed) return std::nullopt;
    return *listed + deliveries_[index].shift_ns;
  }

  std::span<const ImuSample> imu() const override { return imu_; }
  std::span<const std::string> skippedImuRows() const override { return recording_->skippedImuRows(); }
  std::span<const StampedPose> groundTruth() const override { return recording_->groundTruth(); }
  std::span<const GroundTruthState> groundTruthStates() const override { return recording_->groundTruthStates(); }
  std::string describe() const override { return recording_->describe() + "; faults injected: " + plan_.describe(); }

 private:
  /// One frame handed out: which recorded frame, its clock shift, and what happens before it.
  struct Delivery {
    std::size_t source = 0;
    std::int64_t shift_ns = 0;
    std::int64_t stall_ns = 0;
    bool repeat = false;  ///< the previous delivery's frame again
    bool blank = false;   ///< no depth, black colour
  };

  /// Marks the frames K … K+N−1 of a fault that takes a frame count, those of the recording.
  static void markFrames(const Fault& fault, std::vector<bool>& marks) {
    const std::size_t end = std::min(marks.size(), fault.frame + static_cast<std::size_t>(fault.value));
    for (std::size_t i = fault.frame; i < end; ++i) marks[i] = true;
  }

  void planFrames(std::size_t frames) {
    std::vector<std::int64_t> shift_ns(frames, 0), stall_ns(frames, 0);
    std::vector<bool> dropped(frames, false), duplicated(frames, false), blank(frames, false);
    for (const Fault& fault : plan_.faults) {
      const std::int64_t value_ns = secondsToNs(fault.value);
      switch (fault.kind) {
        case FaultKind::kClockJump:
          for (std::size_t i = fault.frame; i < frames; ++i) shift_ns[i] += value_ns;
          break;
        case FaultKind::kTimeBackwards:
          shift_ns[fault.frame] -= value_ns;
          break;
        case FaultKind::kFrameDrop:
          markFrames(fault, dropped);
          break;
        case FaultKind::kFrameDuplicate:
          duplicated[fault.frame] = true;
          break;
        case FaultKind::kFrameBlank:
          markFrames(fault, blank);
          break;
        case FaultKind::kStall:
          stall_ns[fault.frame] += value_ns;
          break;
        default:  // IMU faults (planImu) and device-lost (the caller's)
          break;
      }
    }
    deliveries_.reserve(frames + plan_.faults.size());
    std::int64_t pending_stall_ns = 0;  // a stall before a dropped frame comes before the next one shown
    for (std::size_t i = 0; i < frames; ++i) {
      pending_stall_ns += stall_ns[i];
      if (dropped[i]) continue;
      deliveries_.push_back({i, shift_ns[i], pending_stall_ns, false, blank[i]});
      pending_stall_ns = 0;
      if (duplicated[i]) deliveries_.push_back({i, shift_ns[i], 0, true, blank[i]});
    }
  }

  /// The recorded time between frames K−1 and K, where IMU faults and clock jumps happen.
  std::int64_t momentBefore(std::size_t frame) const {
    const std::optional<std::int64_t> before = recording_->listedFrameTimeNs(frame - 1);
    const std::optional<std::int64_t> at = recording_->listedFrameTimeNs(frame);
    if (!before || !at) {
      throw Error(recording_->describe() + ": lists no frame times, which IMU faults and clock jumps need");
    }
    return *before + (*at - *before) / 2;
  }

  void planImu() {
    const std::span<const ImuSample> recorded = recording_->imu();
    std::vector<SampleFaults> marks(recorded.size());
    std::vector<std::int64_t> shift_ns(recorded.size(), 0);
    const auto firstAtOrAfter = [&](std::int64_t t_ns) {
      return static_cast<std::size_t>(
          std::lower_bound(recorded.begin(), recorded.end(), t_ns,
                           [](const ImuSample& sample, std::int64_t t) { return sample.t_ns < t; }) -
          recorded.begin());
    };
    for (const Fault& fault : plan_.faults) {
      if (!happensBetweenFrames(fault.kind)) continue;
      const std::int64_t moment_ns = momentBefore(fault.frame);
      if (fault.kind == FaultKind::kClockJump) {
        for (std::size_t i = firstAtOrAfter(moment_ns); i < recorded.size(); ++i)
          shift_ns[i] += secondsToNs(fault.value);
        continue;
      }
      if (recorded.empty()) throw Error(recording_->describe() + ": has no IMU samples to inject IMU faults into");
      const std::size_t at = std::min(firstAtOrAfter(moment_ns), recorded.size() - 1);
      switch (fault.kind) {
        case FaultKind::kImuGap: {
          const std::int64_t end_ns = moment_ns + secondsToNs(fault.value);
          for (std::size_t i = firstAtOrAfter(moment_ns); i < recorded.size() && recorded[i].t_ns < end_ns; ++i)
            marks[i].removed = true;
          break;
        }
        case FaultKind::kImuDuplicate:
          marks[at].repeated = true;
          break;
        case FaultKind::kImuReorder:
          marks[at].swapped_with_next = true;
          break;
        case FaultKind::kImuNan:
          marks[at].nan_accel = true;
          break;
        default:
          marks[at].inf_gyro = true;
          break;
      }
    }
    imu_.reserve(recorded.size() + plan_.faults.size());
    const auto emit = [&](std::size_t i) {
      if (marks[i].removed) return;
      ImuSample sample = recorded[i];
      sample.t_ns += shift_ns[i];
      if (marks[i].nan_accel) sample.accel_mps2.x() = std::numeric_limits<double>::quiet_NaN();
      if (marks[i].inf_gyro) sample.gyro_rad_s.z() = std::numeric_limits<double>::infinity();
      imu_.push_back(sample);
      if (marks[i].repeated) imu_.push_back(sample);
    };
    for (std::size_t i = 0; i < recorded.size(); ++i) {
      if (marks[i].swapped_with_next && i + 1 < recorded.size()) {
        emit(i + 1);
        emit(i++);
      } else {
        emit(i);
      }
    }
  }

  std::unique_ptr<DatasetReader> recording_;
  FaultPlan plan_;
  std::vector<Delivery> deliveries_;
  std::size_t next_ = 0;             ///< the next delivery
  std::size_t source_position_ = 0;  ///< the next frame the recording delivers
  RgbdFrame repeated_;               ///< the frame a repeat delivery shows again
  RgbdFrame dropped_;                ///< where dropped frames are read into
  std::vector<ImuSample> imu_;
};

}  // namespace

std::unique_ptr<DatasetReader> withFaults(std::unique_ptr<DatasetReader> recording, const FaultPlan& plan) {
  return std::make_unique<FaultInjectingReader>(std::move(recording), plan);
}

}  // namespace vifusion::datasets
