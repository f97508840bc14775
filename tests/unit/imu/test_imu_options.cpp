#include <gtest/gtest.h>

#include <limits>

#include "vifusion/imu/imu_error.hpp"
#include "vifusion/imu/imu_options.hpp"
#include "vifusion/imu/preintegration.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::imu {
namespace {

using vifusion::test::expectError;

TEST(ImuOptions, DefaultsAreValidAndAllowOneDroppedSample) {
  const ImuOptions options;
  EXPECT_NO_THROW(options.validate());
  EXPECT_EQ(options.maxGapNs(), 12'500'000);  // 2.5 periods of 5 ms
  ImuOptions zr300;
  zr300.noise = ImuNoiseParams::zr300();
  EXPECT_NO_THROW(zr300.validate());
}

TEST(ImuOptions, ValidateNamesTheBadField) {
  const auto expectRejected = [](auto change, const std::string& field) {
    ImuOptions options;
    change(options);
    expectError([&] { options.validate(); }, "'" + field + "'");
    expectError([&] { ImuPreintegrator{options}; }, "'" + field + "'");
    expectError([&] { ImuError(options, SE3d()); }, "'" + field + "'");
  };
  expectRejected([](ImuOptions& o) { o.noise.rate_hz = 0.0; }, "rate_hz");
  expectRejected([](ImuOptions& o) { o.noise.gyro_noise_density = 0.0; }, "noise.gyro_noise_density");
  expectRejected([](ImuOptions& o) { o.noise.accel_noise_density = 0.0; }, "noise.accel_noise_density");
  expectRejected([](ImuOptions& o) { o.noise.gyro_random_walk = 0.0; }, "noise.gyro_random_walk");
  expectRejected([](ImuOptions& o) { o.noise.accel_random_walk = 0.0; }, "noise.accel_random_walk");
  expectRejected([](ImuOptions& o) { o.max_gap_periods = 1.0; }, "max_gap_periods");
  expectRejected([](ImuOptions& o) { o.max_gap_periods = std::numeric_limits<double>::infinity(); }, "max_gap_periods");
  expectRejected([](ImuOptions& o) { o.saturation_noise_factor = 0.5; }, "saturation_noise_factor");
  expectRejected([](ImuOptions& o) { o.reintegrate_above_rad = 0.0; }, "reintegrate_above_rad");
  expectRejected([](ImuOptions& o) { o.gravity_direction_random_walk = std::numeric_limits<double>::quiet_NaN(); },
                 "gravity_direction_random_walk");
}

}  // namespace
}  // namespace vifusion::imu
