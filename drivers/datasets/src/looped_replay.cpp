#include "vifusion/datasets/looped_replay.hpp"

#include <string>
#include <utility>
#include <vector>

#include "vifusion/core/error.hpp"

namespace vifusion::datasets {
namespace {

class LoopedReplay final : public DatasetReader {
 public:
  LoopedReplay(RecordingOpener open, std::size_t passes)
      : open_(std::move(open)), passes_(passes), first_(open_()), current_(first_.get()) {
    const std::size_t frames = first_->frameCount();
    if (first_->live()) throw Error(first_->describe() + ": a live source cannot be replayed");
    const std::optional<std::int64_t> t_first = frames >= 2 ? first_->listedFrameTimeNs(0) : std::nullopt;
    const std::optional<std::int64_t> t_last = frames >= 2 ? first_->listedFrameTimeNs(frames - 1) : std::nullopt;
    if (!t_first || !t_last || *t_last <= *t_first) {
      throw Error(first_->describe() + ": replaying it in a loop needs at least 2 frames with listed times");
    }
    frames_per_pass_ = frames;
    const std::int64_t span_ns = *t_last - *t_first;
    pass_shift_ns_ = span_ns + span_ns / static_cast<std::int64_t>(frames - 1);
    const std::span<const ImuSample> recorded = first_->imu();
    imu_.reserve(recorded.size() * passes_);
    for (std::size_t pass = 0; pass < passes_; ++pass) {
      const std::int64_t shift_ns = static_cast<std::int64_t>(pass) * pass_shift_ns_;
      for (ImuSample sample : recorded) {
        sample.t_ns += shift_ns;
        // Samples from before the first frame (the estimator's gravity window) overlap the previous pass: its own.
        if (imu_.empty() || sample.t_ns > imu_.back().t_ns) imu_.push_back(sample);
      }
    }
  }

  const RigCalibration& calibration() const override { return first_->calibration(); }
  std::size_t frameCount() const override { return frames_per_pass_ * passes_; }

  bool nextFrame(RgbdFrame& frame) override {
    if (delivered_in_pass_ == frames_per_pass_) {
      if (pass_ + 1 == passes_) return false;
      ++pass_;
      delivered_in_pass_ = 0;
      if (!current_->rewind()) {  // a recording read as a stream: its own index, read again
        later_ = open_();
        current_ = later_.get();
      }
    }
    ++delivered_in_pass_;  // a frame that cannot be read is passed all the same
    if (!current_->nextFrame(frame)) {
      delivered_in_pass_ = frames_per_pass_;
      return nextFrame(frame);
    }
    frame.t_ns += static_cast<std::int64_t>(pass_) * pass_shift_ns_;
    frame.index += static_cast<std::int64_t>(pass_ * frames_per_pass_);
    return true;
  }

  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override {
    const std::optional<std::int64_t> listed = first_->listedFrameTimeNs(index % frames_per_pass_);
    if (!listed || index >= frameCount()) return std::nullopt;
    return *listed + static_cast<std::int64_t>(index / frames_per_pass_) * pass_shift_ns_;
  }
  std::span<const ImuSample> imu() const override { return imu_; }
  std::span<const std::string> skippedImuRows() const override { return first_->skippedImuRows(); }
  /// The first pass's: later passes repeat the same motion on a later clock.
  std::span<const StampedPose> groundTruth() const override { return first_->groundTruth(); }
  std::span<const GroundTruthState> groundTruthStates() const override { return first_->groundTruthStates(); }
  std::string describe() const override {
    return first_->describe() + "; replayed " + std::to_string(passes_) + " times end to end";
  }

 private:
  RecordingOpener open_;
  std::size_t passes_;
  std::unique_ptr<DatasetReader> first_;  ///< the first pass, kept for what the source says of itself
  std::unique_ptr<DatasetReader> later_;  ///< the pass now read, where the first could not rewind
  DatasetReader* current_;
  std::size_t frames_per_pass_ = 0;
  std::int64_t pass_shift_ns_ = 0;
  std::size_t pass_ = 0;
  std::size_t delivered_in_pass_ = 0;
  std::vector<ImuSample> imu_;
};

}  // namespace

std::unique_ptr<DatasetReader> loopedReplay(const RecordingOpener& open, std::size_t passes) {
  if (passes < 1) throw Error("a replay needs at least 1 pass, not " + std::to_string(passes));
  return std::make_unique<LoopedReplay>(open, passes);
}

}  // namespace vifusion::datasets
