#include "vifusion/usb_imu/motion_module_options.hpp"

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::usb_imu {
namespace {

constexpr int kMaxCommandTimeoutMs = 10'000;
constexpr int kMaxPumpTimeoutMs = 1'000;

void require(bool ok, const char* field, const std::string& what) {
  if (!ok) throw Error(std::string("MotionModuleOptions.") + field + " " + what);
}

}  // namespace

void MotionModuleOptions::validate() const {
  require(imu_ring_capacity >= 1, "imu_ring_capacity", "must be >= 1, got 0");
  require(frame_event_ring_capacity >= 1, "frame_event_ring_capacity", "must be >= 1, got 0");
  require(raw_transfer_ring_capacity <= kMaxRawTransferRingCapacity, "raw_transfer_ring_capacity",
          "must be at most " + std::to_string(kMaxRawTransferRingCapacity) + ", got " +
              std::to_string(raw_transfer_ring_capacity));
  require(transfers_in_flight >= 1 && transfers_in_flight <= kMaxTransfersInFlight, "transfers_in_flight",
          "must be in [1, " + std::to_string(kMaxTransfersInFlight) + "], got " + std::to_string(transfers_in_flight));
  require(command_timeout_ms > 0 && command_timeout_ms <= kMaxCommandTimeoutMs, "command_timeout_ms",
          "must be in (0, " + std::to_string(kMaxCommandTimeoutMs) + "] ms, got " + std::to_string(command_timeout_ms));
  require(pump_timeout_ms > 0 && pump_timeout_ms <= kMaxPumpTimeoutMs, "pump_timeout_ms",
          "must be in (0, " + std::to_string(kMaxPumpTimeoutMs) + "] ms, got " + std::to_string(pump_timeout_ms));
  ranges.validate();
  merger.validate();
  clock.validate();
}

}  // namespace vifusion::usb_imu
