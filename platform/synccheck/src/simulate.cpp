// simulate(): the clock model of clock_model.hpp, one strobe at a time.
#include <cmath>
#include <random>

#include "vifusion/synccheck/clock_model.hpp"
#include "vifusion/synccheck/zr300_timing.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kPpm = 1e-6;

/// The device clock and the host's mapping of it back, with the mapping's rate off by drift_ppm.
class DeviceClock {
 public:
  explicit DeviceClock(const ClockModel& model)
      : start_ns_(static_cast<double>(model.start_ns)),
        origin_ns_(static_cast<double>(model.device_origin_ns)),
        rate_(1.0 + model.device_skew_ppm * kPpm),
        mapping_error_(1.0 + model.drift_ppm * kPpm) {}

  /// Host time → device ticks (truncated, as a counter reads).
  std::int64_t ticksAt(double host_ns) const {
    return static_cast<std::int64_t>(std::floor((origin_ns_ + (host_ns - start_ns_) * rate_) / kZr300DeviceTickNs));
  }
  /// Device nanoseconds → the first tick at or after them.
  std::int64_t ticksOfDeviceNs(double device_ns) const {
    return static_cast<std::int64_t>(std::ceil(device_ns / kZr300DeviceTickNs));
  }
  /// Device ticks → host time as the (slightly wrong) mapping gives it [ns].
  double mappedHostNs(std::int64_t ticks) const {
    const double device_ns = static_cast<double>(ticks) * kZr300DeviceTickNs;
    return start_ns_ + (device_ns - origin_ns_) / rate_ * mapping_error_;
  }
  double originNs() const { return origin_ns_; }

 private:
  double start_ns_, origin_ns_, rate_, mapping_error_;
};

std::int64_t toNs(double t_ns) { return std::llround(t_ns); }

}  // namespace

SyncInput simulate(const ClockModel& model, std::uint64_t seed, SimulationTruth* truth) {
  model.validate();
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gaussian(0.0, 1.0);
  std::exponential_distribution<double> exponential(1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const DeviceClock clock(model);
  const double period_ns = static_cast<double>(kNsPerSecond) / model.frame_rate_hz;
  const auto strobes = static_cast<std::size_t>(std::floor(model.duration_s * model.frame_rate_hz));
  const auto edgeLatencyNs = [&] {
    return static_cast<double>(model.edge_latency_ns) +
           static_cast<double>(model.edge_latency_spread_ns) * exponential(rng);
  };

  SyncInput input;
  SimulationTruth counts;
  counts.strobes = strobes;
  std::uint64_t sequence = 0;
  std::int64_t index = 0;
  for (std::size_t k = 0; k < strobes; ++k) {
    const double strobe_ns = static_cast<double>(model.start_ns) + static_cast<double>(k) * period_ns;
    input.edges.push_back({toNs(strobe_ns + edgeLatencyNs()), true, sequence++});
    input.edges.push_back(
        {toNs(strobe_ns + static_cast<double>(model.strobe_width_ns) + edgeLatencyNs()), false, sequence++});

    const double event_host_ns =
        strobe_ns + static_cast<double>(model.offset_ns) + static_cast<double>(model.jitter_ns) * gaussian(rng);
    const std::int64_t event_ns = toNs(clock.mappedHostNs(clock.ticksAt(event_host_ns)));
    const std::int64_t kernel_ns = toNs(strobe_ns + static_cast<double>(model.kernel_offset_ns) +
                                        static_cast<double>(model.kernel_jitter_ns) * gaussian(rng));
    const bool has_event = uniform(rng) < model.event_probability;
    const bool at_an_end = k == 0 || k + 1 == strobes;  // drops there could not be seen: never dropped
    const bool dropped = uniform(rng) < model.drop_probability && !at_an_end;
    const bool duplicated = uniform(rng) < model.duplicate_probability;
    if (dropped) {
      ++counts.dropped_frames;
      continue;
    }
    CameraFrameTimes frame{.index = 0,
                           .device_frame_number = model.first_frame_number + static_cast<std::uint32_t>(k),
                           .t_ns = has_event ? event_ns : kernel_ns,
                           .kernel_mid_ns = kernel_ns,
                           .device_event_ns = has_event ? event_ns : 0,
                           .stamped_by_device_event = has_event};
    const int deliveries = duplicated ? 2 : 1;
    for (int copy = 0; copy < deliveries; ++copy) {
      frame.index = index++;
      input.frames.push_back(frame);
      if (!has_event) ++counts.kernel_stamped_frames;
    }
    if (duplicated) ++counts.duplicated_frames;
  }

  // IMU samples every 1/imu_rate_hz of DEVICE time, mapped like the events; a residual per packet.
  const double imu_period_device_ns = static_cast<double>(kNsPerSecond) / model.imu_rate_hz;
  const double end_ns = static_cast<double>(model.start_ns) + model.duration_s * static_cast<double>(kNsPerSecond);
  for (std::size_t j = 0;; ++j) {
    const double device_ns = clock.originNs() + static_cast<double>(j) * imu_period_device_ns;
    const double mapped_ns = clock.mappedHostNs(clock.ticksOfDeviceNs(device_ns));
    if (mapped_ns > end_ns) break;
    const std::int64_t t_ns = toNs(mapped_ns + static_cast<double>(model.imu_jitter_ns) * gaussian(rng));
    input.imu_t_ns.push_back(t_ns);
    if (j % kZr300ImuEntriesPerPacket == kZr300ImuEntriesPerPacket - 1) {
      const double latency_ns = static_cast<double>(model.mapper_latency_mean_ns) * exponential(rng);
      input.clock_residuals.push_back({toNs(mapped_ns + latency_ns), latency_ns});
    }
  }
  if (truth != nullptr) *truth = counts;
  return input;
}

}  // namespace vifusion::synccheck
