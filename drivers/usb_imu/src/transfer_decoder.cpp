#include "vifusion/usb_imu/transfer_decoder.hpp"

#include <limits>

#include "vifusion/clock/tick_clock.hpp"

namespace vifusion::usb_imu {
namespace {

/// Signed distance from `from` to `to` on the 32-bit tick circle [ticks]: positive when `to` is newer.
std::int64_t tickDistance(std::uint32_t from, std::uint32_t to) {
  return static_cast<std::int64_t>(static_cast<std::int32_t>(to - from));
}

}  // namespace

TransferDecoder::TransferDecoder(const MotionModuleOptions& options, SpscRing<ImuSample>& imu_ring,
                                 SpscRing<DepthFrameEvent>& frame_ring)
    : require_valid_clock_((options.validate(), options.require_valid_clock)),
      step_confirm_transfers_(options.clock.step_confirm_samples),
      imu_ring_(imu_ring),
      frame_ring_(frame_ring),
      ticks_(clock::kZr300TickCounterBits),
      mapper_(options.clock),
      scaler_(options.ranges),
      merger_(options.merger) {}

void TransferDecoder::decode(std::span<const std::uint8_t> transfer, std::int64_t host_receive_ns) {
  bump(transfers_);
  if (transfer.empty()) {
    bump(empty_transfers_);
    return;
  }
  const motion::PacketParserStats before = parser_.stats();
  parser_.parse(transfer, parsed_);
  const motion::PacketParserStats& after = parser_.stats();
  bump(packets_accepted_, after.packets_accepted - before.packets_accepted);
  for (std::size_t reason = 0; reason < motion::kPacketDropReasonCount; ++reason) {
    bump(parse_drops_[reason], after.drop_counts[reason] - before.drop_counts[reason]);
  }
  if (parsed_.imuEntries().empty() && parsed_.timestampEntries().empty()) return;
  if (!unwrapTicks(parsed_)) return;

  const std::int64_t newest_device_ns = clock::zr300TicksToNs(ticks_.count());
  if (!mapper_.addSample(newest_device_ns, host_receive_ns).accepted()) bump(clock_rejected_);
  publishClockState();
  publishImu(parsed_);
  publishFrameEvents(parsed_);
}

bool TransferDecoder::unwrapTicks(const motion::ParsedTransfer& parsed) {
  // The newest tick of the transfer: entries are roughly in order, but a gyro sample may be a few ticks
  // older than the accelerometer sample before it, so take the maximum on the tick circle.
  const std::uint32_t first =
      parsed.imuEntries().empty() ? parsed.timestampEntries().front().ticks : parsed.imuEntries().front().ticks;
  std::int64_t newest = 0;
  for (const motion::ImuEntry& entry : parsed.imuEntries()) newest = std::max(newest, tickDistance(first, entry.ticks));
  for (const motion::TimestampEntry& entry : parsed.timestampEntries()) {
    newest = std::max(newest, tickDistance(first, entry.ticks));
  }
  const clock::CounterUpdate update = ticks_.update(static_cast<std::uint32_t>(first + newest));
  if (update.applied()) return true;
  if (update.step == clock::CounterStep::kRepeat) return true;  // same newest tick: entries still placeable
  bump(tick_backward_);
  if (ticks_.consecutiveBackward() >= step_confirm_transfers_) ticks_.reset();
  return false;
}

bool TransferDecoder::mapTicks(std::uint32_t raw_ticks, std::int64_t& device_ns, std::int64_t& host_ns) {
  const std::int64_t count = ticks_.nearestCount(raw_ticks);
  if (count < 0) return false;  // before the first tick the unwrapper saw: no place on the time base
  if (require_valid_clock_ && !mapper_.valid()) return false;
  device_ns = clock::zr300TicksToNs(count);
  const std::optional<std::int64_t> mapped = mapper_.toHostNs(device_ns);
  if (!mapped) return false;
  host_ns = *mapped;
  return true;
}

void TransferDecoder::publishImu(const motion::ParsedTransfer& parsed) {
  for (const motion::ImuEntry& entry : parsed.imuEntries()) {
    std::int64_t device_ns = 0;
    std::int64_t t_ns = 0;
    if (!mapTicks(entry.ticks, device_ns, t_ns)) {
      bump(unmapped_samples_);
      continue;
    }
    if (entry.source == motion::EventSource::kAccelerometer) {
      merger_.pushAccel(t_ns, scaler_.accelMps2(entry.raw_xyz));
    } else {
      merger_.pushGyro(t_ns, scaler_.gyroRadS(entry.raw_xyz));
    }
    ImuSample sample;
    while (merger_.popMerged(sample)) {
      if (imu_ring_.tryPush(sample)) {
        bump(imu_samples_);
      } else {
        bump(imu_overruns_);
      }
    }
  }
  const std::uint64_t merger_drops = merger_.stats().totalDrops();
  bump(merge_drops_, merger_drops - merger_drops_seen_);
  merger_drops_seen_ = merger_drops;
}

void TransferDecoder::publishFrameEvents(const motion::ParsedTransfer& parsed) {
  for (const motion::TimestampEntry& entry : parsed.timestampEntries()) {
    if (entry.source != motion::EventSource::kDepthFrame) continue;  // fisheye and GPIO: not used here
    DepthFrameEvent event{.frame_counter = entry.frame_counter};
    if (!mapTicks(entry.ticks, event.device_ns, event.t_ns)) {
      bump(unmapped_samples_);
      continue;
    }
    if (frame_ring_.tryPush(event)) {
      bump(frame_events_);
    } else {
      bump(frame_event_overruns_);
    }
  }
}

void TransferDecoder::publishClockState() {
  clock_state_.store(mapper_.state(), std::memory_order_relaxed);
  clock_offset_ns_.store(mapper_.offsetNs(), std::memory_order_relaxed);
  clock_skew_ppm_.store(mapper_.skewPpm(), std::memory_order_relaxed);
}

MotionModuleStats TransferDecoder::stats() const {
  MotionModuleStats out;
  const auto load = [](const Counter& counter) { return counter.load(std::memory_order_relaxed); };
  out.transfers = load(transfers_);
  out.empty_transfers = load(empty_transfers_);
  out.packets_accepted = load(packets_accepted_);
  for (std::size_t reason = 0; reason < motion::kPacketDropReasonCount; ++reason) {
    out.parse_drops[reason] = load(parse_drops_[reason]);
  }
  out.tick_backward = load(tick_backward_);
  out.clock_rejected = load(clock_rejected_);
  out.unmapped_samples = load(unmapped_samples_);
  out.merge_drops = load(merge_drops_);
  out.imu_samples = load(imu_samples_);
  out.imu_overruns = load(imu_overruns_);
  out.frame_events = load(frame_events_);
  out.frame_event_overruns = load(frame_event_overruns_);
  out.clock_state = clock_state_.load(std::memory_order_relaxed);
  out.clock_offset_ns = clock_offset_ns_.load(std::memory_order_relaxed);
  out.clock_skew_ppm = clock_skew_ppm_.load(std::memory_order_relaxed);
  return out;
}

void TransferDecoder::reset() {
  parser_.reset();
  ticks_.reset();
  mapper_.reset();
  merger_.reset();
  merger_drops_seen_ = 0;
  publishClockState();
}

}  // namespace vifusion::usb_imu
