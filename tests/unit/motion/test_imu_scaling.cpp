// Raw motion-module words to rad/s and m/s² at the documented ranges, including the configurable ones.

#include <gtest/gtest.h>

#include <numbers>

#include "vifusion/motion/imu_scaling.hpp"
#include "vifusion/test/expect_error.hpp"

namespace vifusion::motion {
namespace {

constexpr double kTolerance = 1e-12;
constexpr double kDegToRad = std::numbers::pi / 180.0;

TEST(ImuScaling, GyroFullScaleZeroAndNegative) {
  const ImuScaler scaler;
  const Eigen::Vector3d rate = scaler.gyroRadS({32767, 0, -32767});
  EXPECT_NEAR(rate.x(), 1000.0 * kDegToRad, kTolerance);  // 17.453292519943 rad/s
  EXPECT_NEAR(rate.x(), 17.453292519943297, kTolerance);
  EXPECT_EQ(rate.y(), 0.0);
  EXPECT_NEAR(rate.z(), -17.453292519943297, kTolerance);
  // The most negative word is one count past full scale.
  EXPECT_NEAR(scaler.gyroRadS({-32768, 0, 0}).x(), -17.453292519943297 * 32768.0 / 32767.0, kTolerance);
  EXPECT_NEAR(scaler.gyroRadSPerCount(), 17.453292519943297 / 32767.0, kTolerance);
}

TEST(ImuScaling, AccelUsesTheTwelveMostSignificantBits) {
  const ImuScaler scaler;
  // 1 g at ±4 g is 512 counts of 12 bits, i.e. the word 512 << 4 = 8192.
  EXPECT_NEAR(scaler.accelMps2({0, 0, 8192}).z(), 9.80665, kTolerance);
  // Full scale: +2047 counts (word 0x7FF0) and −2048 counts (word 0x8000 = −32768, exactly −4 g).
  const Eigen::Vector3d extremes = scaler.accelMps2({0x7FF0, -32768, 0});
  EXPECT_NEAR(extremes.x(), 2047.0 * 4.0 * 9.80665 / 2048.0, kTolerance);  // 39.20744 m/s²
  EXPECT_NEAR(extremes.y(), -4.0 * 9.80665, kTolerance);                   // −39.2266 m/s²
  EXPECT_EQ(extremes.z(), 0.0);
  // The low 4 bits are not data; the shift is arithmetic, so −1 and −16 are both −1 count.
  const Eigen::Vector3d small = scaler.accelMps2({15, -1, -16});
  EXPECT_EQ(small.x(), 0.0);
  EXPECT_NEAR(small.y(), -9.80665 * 4.0 / 2048.0, kTolerance);  // −0.019153613 m/s²
  EXPECT_NEAR(small.z(), small.y(), kTolerance);
}

TEST(ImuScaling, OtherRangesAreOneOptionAway) {
  const ImuScaler wide({.gyro_full_scale_deg_s = 2000.0, .accel_full_scale_g = 16.0});
  EXPECT_NEAR(wide.gyroRadS({32767, 0, 0}).x(), 2000.0 * kDegToRad, kTolerance);
  EXPECT_NEAR(wide.accelMps2({-32768, 0, 0}).x(), -16.0 * 9.80665, kTolerance);
  const ImuScaler eight_g({.accel_full_scale_g = 8.0});
  EXPECT_NEAR(eight_g.accelMps2({0, 0, 8192}).z(), 2.0 * 9.80665, kTolerance);
}

TEST(ImuScaling, RangesTheModuleDoesNotOfferAreRefusedByName) {
  vifusion::test::expectError([] { ImuScaler({.gyro_full_scale_deg_s = 500.0}); },
                              "'gyro_full_scale_deg_s' = 500 is not a range the motion module offers (1000 or 2000)");
  vifusion::test::expectError([] { ImuScaler({.accel_full_scale_g = 2.0}); },
                              "'accel_full_scale_g' = 2 is not a range the motion module offers (4 or 8 or 16)");
}

}  // namespace
}  // namespace vifusion::motion
