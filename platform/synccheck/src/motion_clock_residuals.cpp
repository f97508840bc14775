#include "vifusion/synccheck/motion_clock_residuals.hpp"

#include <algorithm>
#include <optional>

#include "vifusion/clock/clock_mapper.hpp"
#include "vifusion/clock/counter_unwrapper.hpp"
#include "vifusion/clock/tick_clock.hpp"
#include "vifusion/motion/packet_parser.hpp"
#include "vifusion/motion/parsed_transfer.hpp"

namespace vifusion::synccheck {
namespace {

/// Signed distance from `from` to `to` on the 32-bit tick circle [ticks]: positive when `to` is newer.
std::int64_t tickDistance(std::uint32_t from, std::uint32_t to) {
  return static_cast<std::int64_t>(static_cast<std::int32_t>(to - from));
}

}  // namespace

std::vector<ClockResidualSample> motionClockResiduals(std::span<const MotionTransferBytes> transfers,
                                                      const clock::ClockMapperOptions& options) {
  motion::PacketParser parser;
  motion::ParsedTransfer parsed;
  clock::CounterUnwrapper ticks(clock::kZr300TickCounterBits);
  clock::ClockMapper mapper(options);
  std::vector<ClockResidualSample> residuals;
  residuals.reserve(transfers.size());
  for (const MotionTransferBytes& transfer : transfers) {
    parser.parse(transfer.bytes, parsed);
    if (parsed.imuEntries().empty() && parsed.timestampEntries().empty()) continue;
    // The transfer's newest tick, as the driver takes it (usb_imu/transfer_decoder.cpp): entries are nearly
    // in order, so the maximum on the tick circle from the first one.
    const std::uint32_t first =
        parsed.imuEntries().empty() ? parsed.timestampEntries().front().ticks : parsed.imuEntries().front().ticks;
    std::int64_t newest = 0;
    for (const motion::ImuEntry& entry : parsed.imuEntries())
      newest = std::max(newest, tickDistance(first, entry.ticks));
    for (const motion::TimestampEntry& entry : parsed.timestampEntries()) {
      newest = std::max(newest, tickDistance(first, entry.ticks));
    }
    const clock::CounterUpdate update = ticks.update(static_cast<std::uint32_t>(first + newest));
    if (!update.applied()) continue;
    const std::int64_t device_ns = clock::zr300TicksToNs(ticks.count());
    mapper.addSample(device_ns, transfer.host_receive_ns);
    if (!mapper.valid()) continue;
    if (const std::optional<std::int64_t> mapped = mapper.toHostNs(device_ns)) {
      residuals.push_back({transfer.host_receive_ns, static_cast<double>(transfer.host_receive_ns - *mapped)});
    }
  }
  return residuals;
}

}  // namespace vifusion::synccheck
