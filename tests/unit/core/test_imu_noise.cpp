#include <gtest/gtest.h>

#include <limits>

#include "vifusion/core/error.hpp"
#include "vifusion/core/imu_noise.hpp"

namespace vifusion {
namespace {

TEST(ImuNoiseParams, PresetsAreTheColumnsOfTableOne) {
  const ImuNoiseParams synthetic = ImuNoiseParams::preset("synthetic");
  EXPECT_EQ(synthetic.accel_noise_density, 8.0e-3);
  EXPECT_EQ(synthetic.accel_bias_prior, 0.1);
  EXPECT_TRUE(synthetic.static_accel_bias_mps2.isZero());
  const ImuNoiseParams zr300 = ImuNoiseParams::preset("zr300");
  EXPECT_EQ(zr300.accel_noise_density, 8.0e-2);
  EXPECT_EQ(zr300.accel_bias_prior, 1.0);
  EXPECT_EQ(zr300.static_accel_bias_mps2, Eigen::Vector3d(0.060, 0.258, 0.126));
  for (const ImuNoiseParams& p : {synthetic, zr300}) {
    EXPECT_EQ(p.gyro_noise_density, 12.0e-4);
    EXPECT_EQ(p.gyro_random_walk, 4.0e-6);
    EXPECT_EQ(p.accel_random_walk, 2.0e-5);
    EXPECT_EQ(p.gyro_saturation_rad_s, 7.8);
    EXPECT_EQ(p.accel_saturation_mps2, 176.0);
    EXPECT_EQ(p.rate_hz, 200.0);
    EXPECT_NO_THROW(p.validate());
  }
}

TEST(ImuNoiseParams, RejectsUnknownPresetsAndBadValuesByName) {
  try {
    ImuNoiseParams::preset("synthetc");
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("'synthetc'"), std::string::npos);
  }
  ImuNoiseParams p;
  p.rate_hz = 0.0;
  try {
    p.validate();
    FAIL();
  } catch (const Error& error) {
    EXPECT_NE(std::string(error.what()).find("rate_hz"), std::string::npos);
  }
  p = ImuNoiseParams{};
  p.gyro_noise_density = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(p.validate(), Error);
}

}  // namespace
}  // namespace vifusion
