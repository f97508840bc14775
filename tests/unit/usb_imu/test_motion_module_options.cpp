#include <gtest/gtest.h>

#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/usb_imu/motion_module_options.hpp"

namespace vifusion::usb_imu {
namespace {

std::string validationMessage(const MotionModuleOptions& options) {
  try {
    options.validate();
  } catch (const Error& error) {
    return error.what();
  }
  return {};
}

TEST(MotionModuleOptions, DefaultsAreValid) { EXPECT_EQ(validationMessage({}), ""); }

TEST(MotionModuleOptions, EachBadFieldIsNamed) {
  MotionModuleOptions options;
  options.imu_ring_capacity = 0;
  EXPECT_NE(validationMessage(options).find("imu_ring_capacity"), std::string::npos);
  options = {};
  options.frame_event_ring_capacity = 0;
  EXPECT_NE(validationMessage(options).find("frame_event_ring_capacity"), std::string::npos);
  options = {};
  options.transfers_in_flight = MotionModuleOptions::kMaxTransfersInFlight + 1;
  EXPECT_NE(validationMessage(options).find("transfers_in_flight must be in [1, 32], got 33"), std::string::npos);
  options = {};
  options.command_timeout_ms = 0;
  EXPECT_NE(validationMessage(options).find("command_timeout_ms"), std::string::npos);
  options = {};
  options.pump_timeout_ms = 5000;
  EXPECT_NE(validationMessage(options).find("pump_timeout_ms"), std::string::npos);
  options = {};
  options.ranges.accel_full_scale_g = 3.0;  // nested options are checked too
  EXPECT_NE(validationMessage(options).find("accel_full_scale_g"), std::string::npos);
}

}  // namespace
}  // namespace vifusion::usb_imu
