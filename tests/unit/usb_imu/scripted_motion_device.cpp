#include "scripted_motion_device.hpp"

#include <chrono>
#include <cmath>
#include <thread>

#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/motion/imu_scaling.hpp"
#include "vifusion/motion/packet_encoder.hpp"
#include "vifusion/motion/packet_format.hpp"
#include "vifusion/test/counting_allocations.hpp"

namespace vifusion::usb_imu::test {
namespace {

constexpr std::uint16_t kCounterMask = motion::kTagCounterMask;
/// Accelerometer word of 1 g on a ±4 g range: 512 counts in the 12 MSBs.
constexpr std::int16_t kOneGAccelWord = 512 << motion::kAccelDataShiftBits;
constexpr std::uint16_t kErrorBitImuFifoOverflow = 1u << static_cast<unsigned>(motion::ErrorFlag::kImuFifoOverflow);
constexpr std::size_t kShortTransferBytes = 50;
constexpr int kIdlePumpSleepMs = 1;

/// A reproducible pseudo-random value in [0, 1) for transfer i (a 64-bit mix, no state).
double unitHash(std::uint64_t i) {
  std::uint64_t x = i * 0x9E3779B97F4A7C15ull;
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ull;
  x ^= x >> 29;
  return static_cast<double>(x >> 11) / static_cast<double>(1ull << 53);
}

std::uint32_t ticksAt(std::uint32_t first_tick, std::int64_t device_offset_ns) {
  return first_tick + static_cast<std::uint32_t>(clock::nsToTicks(device_offset_ns, clock::kZr300MotionTicksPerSecond));
}

}  // namespace

ScriptedMotionDevice::ScriptedMotionDevice(const ScriptOptions& options) : options_(options) { buildStream(); }

std::int64_t ScriptedMotionDevice::trueHostNs(std::int64_t device_offset_ns) const {
  return options_.host_offset_ns + std::llround(static_cast<double>(device_offset_ns) * (1.0 + options_.skew)) +
         options_.min_latency_ns;
}

void ScriptedMotionDevice::buildStream() {
  const auto total_ns = static_cast<std::int64_t>(options_.duration_s * 1e9);
  std::int64_t next_gyro_ns = 0;
  std::int64_t next_frame_ns = 0;
  std::uint16_t accel_counter = 0;
  std::uint16_t gyro_counter = 0;
  std::uint16_t frame_counter = 0;
  std::size_t corrupt_kind = 0;
  std::size_t corrupt_index = 0;
  for (std::int64_t t = 0; t < total_ns; t += options_.transfer_period_ns) {
    const std::size_t index = offsets_.size();
    std::int64_t newest_ns = t;
    motion::MotionPacket packet;
    auto& accel = packet.imu[packet.header.imu_entry_count++];
    accel = {.source = motion::EventSource::kAccelerometer,
             .sample_counter = accel_counter,
             .valid = true,
             .ticks = ticksAt(options_.first_tick, t),
             .raw_xyz = {0, 0, kOneGAccelWord}};
    accel_counter = (accel_counter + 1) & kCounterMask;
    while (next_gyro_ns <= t) {
      // Gyro x carries its own sample counter so a test can tell which sample an ImuSample came from.
      auto& gyro = packet.imu[packet.header.imu_entry_count++];
      gyro = {.source = motion::EventSource::kGyroscope,
              .sample_counter = gyro_counter,
              .valid = true,
              .ticks = ticksAt(options_.first_tick, next_gyro_ns),
              .raw_xyz = {static_cast<std::int16_t>(gyro_counter), -200, 3000}};
      gyro_counter = (gyro_counter + 1) & kCounterMask;
      next_gyro_ns += options_.gyro_period_ns;
    }
    while (next_frame_ns <= t) {
      auto& frame = packet.timestamps[packet.header.timestamp_entry_count++];
      frame = {.source = motion::EventSource::kDepthFrame,
               .frame_counter = frame_counter,
               .valid = true,
               .ticks = ticksAt(options_.first_tick, next_frame_ns)};
      frame_counter = (frame_counter + 1) & kCounterMask;
      next_frame_ns += options_.frame_period_ns;
    }
    packet.header.cx3_packet_counter = static_cast<std::uint8_t>(index % motion::kCx3CounterModulus);
    std::int64_t latency_ns =
        options_.min_latency_ns + static_cast<std::int64_t>(unitHash(index) * static_cast<double>(options_.jitter_ns));
    if (options_.outlier_every > 0 && index % options_.outlier_every == options_.outlier_every - 1) {
      latency_ns += options_.outlier_ns;
    }
    const std::int64_t host_ns = trueHostNs(newest_ns) - options_.min_latency_ns + latency_ns;
    if (corrupt_index < options_.corrupt_at.size() && options_.corrupt_at[corrupt_index] == index) {
      appendCorrupt(static_cast<CorruptKind>(corrupt_kind++ % kCorruptKindCount), host_ns);
      ++corrupt_index;
      // The corrupt transfer replaces this one's IMU data: counters move on as if the samples were lost.
      continue;
    }
    appendTransfer(packet, host_ns);
  }
}

void ScriptedMotionDevice::appendTransfer(const motion::MotionPacket& packet, std::int64_t host_ns) {
  const std::size_t offset = stream_bytes_.size();
  stream_bytes_.resize(offset + motion::kPacketBytes);
  const std::size_t bytes =
      motion::encodeTransfer(std::span(&packet, 1), std::span(stream_bytes_).subspan(offset, motion::kPacketBytes));
  offsets_.push_back(offset);
  sizes_.push_back(bytes);
  host_ns_.push_back(host_ns);
}

void ScriptedMotionDevice::appendCorrupt(CorruptKind kind, std::int64_t host_ns) {
  motion::MotionPacket packet;
  switch (kind) {
    case CorruptKind::kErrorBits:
      packet.header.error_bitmask = kErrorBitImuFifoOverflow;
      appendTransfer(packet, host_ns);
      return;
    case CorruptKind::kShortTransfer:
      appendTransfer(packet, host_ns);
      sizes_.back() = kShortTransferBytes;
      return;
    case CorruptKind::kImuCountTooLarge:
      packet.header.imu_entry_count = motion::kImuSlotCount + 3;
      appendTransfer(packet, host_ns);
      return;
  }
}

UsbStatus ScriptedMotionDevice::open(int interface_number) {
  if (unplugged_.load()) return UsbStatus::kNoDevice;
  claimed_interface_ = interface_number;
  closed_.store(false);
  return UsbStatus::kOk;
}

UsbStatus ScriptedMotionDevice::bulkWrite(std::uint8_t endpoint, std::span<const std::uint8_t> bytes, int) {
  if (unplugged_.load()) return UsbStatus::kNoDevice;
  const motion::AdapterRequest request = motion::decodeRequest(bytes);
  {
    const std::lock_guard lock(mutex_);
    requests_.push_back({.endpoint = endpoint,
                         .bytes = {bytes.begin(), bytes.end()},
                         .opcode = request.opcode,
                         .param = request.params[0]});
  }
  const motion::AdapterOpcode echoed =
      options_.wrong_reply_opcode ? motion::AdapterOpcode::kGetVersion : request.opcode;
  reply_.assign(motion::kReplyOpcodeBytes, 0);
  motion::encodeReply(echoed, {}, reply_);
  return UsbStatus::kOk;
}

UsbStatus ScriptedMotionDevice::bulkRead(std::uint8_t endpoint, std::span<std::uint8_t> buffer, std::size_t& received,
                                         int) {
  received = 0;
  if (unplugged_.load()) return UsbStatus::kNoDevice;
  if (endpoint != motion::kCommandInEndpoint || reply_.empty()) return UsbStatus::kTimeout;
  std::copy(reply_.begin(), reply_.end(), buffer.begin());
  received = reply_.size();
  reply_.clear();
  return UsbStatus::kOk;
}

UsbStatus ScriptedMotionDevice::startInterrupt(std::uint8_t endpoint, std::size_t, InterruptSink& sink) {
  if (unplugged_.load()) return UsbStatus::kNoDevice;
  interrupt_endpoint_ = endpoint;
  sink_ = &sink;
  return UsbStatus::kOk;
}

UsbStatus ScriptedMotionDevice::pumpInterrupt(int) {
  if (unplugged_.load()) return UsbStatus::kNoDevice;
  std::size_t next = next_transfer_.load();
  if (next >= offsets_.size()) {
    finished_.store(true);
    std::this_thread::sleep_for(std::chrono::milliseconds(kIdlePumpSleepMs));
    return UsbStatus::kTimeout;
  }
  for (std::size_t i = 0; i < options_.transfers_per_pump && next < offsets_.size(); ++i, ++next) {
    if (options_.unplug_after && next == *options_.unplug_after) {
      unplugged_.store(true);
      return UsbStatus::kNoDevice;
    }
    if (next == kAllocationProbeTransfer) allocations_at_probe_.store(vifusion::test::heapAllocationCount());
    sink_->onInterruptTransfer(std::span(stream_bytes_).subspan(offsets_[next], sizes_[next]), host_ns_[next]);
    next_transfer_.store(next + 1);
  }
  if (next >= offsets_.size()) allocations_at_end_.store(vifusion::test::heapAllocationCount());
  return UsbStatus::kOk;
}

void ScriptedMotionDevice::stopInterrupt() { sink_ = nullptr; }

void ScriptedMotionDevice::close() { closed_.store(true); }

std::vector<RecordedRequest> ScriptedMotionDevice::requests() const {
  const std::lock_guard lock(mutex_);
  return requests_;
}

}  // namespace vifusion::usb_imu::test
