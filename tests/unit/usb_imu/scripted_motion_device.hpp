#pragma once
// A scripted ZR300 motion module behind the UsbLink seam: it decodes the driver's adapter requests with
// motion::decodeRequest, answers with motion::encodeReply, and streams interrupt transfers built with
// motion::encodeTransfer from a known motion: device ticks at 32 MHz (optionally starting just before the
// 32-bit wrap), host arrival = offset + (1 + skew)·device time + latency (min latency plus deterministic
// jitter and periodic outliers). Every byte the driver sees comes from the documented layouts.
//
// The whole stream is encoded at construction, so delivering it allocates nothing; the device records the
// heap allocation count at two transfer indices (on the driver thread) for the allocation test.

#include <atomic>
#include <cstdint>
#include <mutex>
#include <optional>
#include <vector>

#include "vifusion/motion/adapter_command.hpp"
#include "vifusion/motion/motion_packet.hpp"
#include "vifusion/usb_imu/usb_link.hpp"

namespace vifusion::usb_imu::test {

struct ScriptOptions {
  double duration_s = 10.0;                     ///< device time streamed
  std::int64_t transfer_period_ns = 4'000'000;  ///< one transfer (one packet) per accelerometer sample, 250 Hz
  std::int64_t gyro_period_ns = 5'000'000;      ///< 200 Hz
  std::int64_t frame_period_ns = 33'333'333;    ///< 30 Hz depth frames
  std::uint32_t first_tick = 0;                 ///< device tick at stream start
  std::int64_t host_offset_ns = 7'000'000'000;  ///< host CLOCK_MONOTONIC at device time 0 of the stream
  double skew = 50e-6;                          ///< host rate / device rate − 1
  std::int64_t min_latency_ns = 100'000;
  std::int64_t jitter_ns = 400'000;  ///< latency = min + (pseudo-random in [0, jitter))
  std::size_t outlier_every = 20;    ///< every Nth transfer is late by outlier_ns
  std::int64_t outlier_ns = 3'000'000;
  std::size_t transfers_per_pump = 25;      ///< delivered per pumpInterrupt() call
  std::optional<std::size_t> unplug_after;  ///< transfers delivered before the device vanishes
  std::vector<std::size_t> corrupt_at;      ///< transfer indices replaced by corrupt ones (cycling kinds)
  bool wrong_reply_opcode = false;          ///< echo another opcode in every reply
};

/// Kinds of corrupt transfers, used in order for ScriptOptions::corrupt_at.
enum class CorruptKind { kErrorBits, kShortTransfer, kImuCountTooLarge };
inline constexpr std::size_t kCorruptKindCount = 3;

struct RecordedRequest {
  std::uint8_t endpoint = 0;
  std::vector<std::uint8_t> bytes;
  motion::AdapterOpcode opcode = motion::AdapterOpcode::kGetVersion;
  std::uint32_t param = 0;
};

class ScriptedMotionDevice final : public UsbLink {
 public:
  explicit ScriptedMotionDevice(const ScriptOptions& options);

  UsbStatus open(int interface_number) override;
  UsbStatus bulkWrite(std::uint8_t endpoint, std::span<const std::uint8_t> bytes, int timeout_ms) override;
  UsbStatus bulkRead(std::uint8_t endpoint, std::span<std::uint8_t> buffer, std::size_t& received,
                     int timeout_ms) override;
  UsbStatus startInterrupt(std::uint8_t endpoint, std::size_t transfer_bytes, InterruptSink& sink) override;
  UsbStatus pumpInterrupt(int timeout_ms) override;
  void stopInterrupt() override;
  void close() override;

  // ---- test side (read after the stream finished or the module stopped) ----
  bool finished() const { return finished_.load(); }
  std::vector<RecordedRequest> requests() const;
  int claimedInterface() const { return claimed_interface_; }
  std::uint8_t interruptEndpoint() const { return interrupt_endpoint_; }
  bool closed() const { return closed_.load(); }
  std::size_t transfersDelivered() const { return next_transfer_.load(); }
  /// Heap allocations (whole process) when transfer `allocation_probe_first` and the last were delivered.
  std::uint64_t allocationsAtProbe() const { return allocations_at_probe_.load(); }
  std::uint64_t allocationsAtEnd() const { return allocations_at_end_.load(); }
  static constexpr std::size_t kAllocationProbeTransfer = 500;

  /// Truth for the assertions: the host time [ns] of device time `device_offset_ns` after stream start,
  /// on the minimum-latency line the mapper can find.
  std::int64_t trueHostNs(std::int64_t device_offset_ns) const;
  const ScriptOptions& options() const { return options_; }
  std::size_t transferCount() const { return offsets_.size(); }
  /// The bytes of transfer `index` (< transferCount()), for a device emulated below libusb.
  std::span<const std::uint8_t> transferBytes(std::size_t index) const {
    return std::span(stream_bytes_).subspan(offsets_[index], sizes_[index]);
  }

 private:
  void buildStream();
  void appendTransfer(const motion::MotionPacket& packet, std::int64_t host_ns);
  void appendCorrupt(CorruptKind kind, std::int64_t host_ns);

  ScriptOptions options_;
  std::vector<std::uint8_t> stream_bytes_;
  std::vector<std::size_t> offsets_;  ///< start of each transfer in stream_bytes_
  std::vector<std::size_t> sizes_;
  std::vector<std::int64_t> host_ns_;
  std::vector<std::uint8_t> reply_;
  mutable std::mutex mutex_;
  std::vector<RecordedRequest> requests_;
  InterruptSink* sink_ = nullptr;
  int claimed_interface_ = -1;
  std::uint8_t interrupt_endpoint_ = 0;
  std::atomic<std::size_t> next_transfer_{0};
  std::atomic<bool> finished_{false};
  std::atomic<bool> unplugged_{false};
  std::atomic<bool> closed_{false};
  std::atomic<std::uint64_t> allocations_at_probe_{0};
  std::atomic<std::uint64_t> allocations_at_end_{0};
};

}  // namespace vifusion::usb_imu::test
