#pragma once
// Starting and stopping the IMU event stream, as data: the USB module sends each step's request, checks
// the reply with decodeReply(step.opcode, …), then waits wait_after_ns before the next step.
//
// Start (librealsense v1.12.4, idle → motion events): first both switched off, so a module left running
// by a crashed process starts from a known state; then MMPWR = 1 (motion module and fisheye powered), a
// 300 ms wait for the module to boot before it can accept the start, then MM_ACTIVATE = 1.
// Stop: MM_ACTIVATE = 0, then MMPWR = 0 (this also powers the fisheye down; vifusion does not use it).

#include <array>
#include <cstdint>

#include "vifusion/core/time.hpp"
#include "vifusion/motion/adapter_command.hpp"

namespace vifusion::motion {

inline constexpr std::uint32_t kSwitchOff = 0;
inline constexpr std::uint32_t kSwitchOn = 1;
/// Between powering the motion module and starting its event stream.
inline constexpr std::int64_t kPowerUpToActivateWaitNs = 300 * kNsPerMillisecond;

struct AdapterStep {
  AdapterOpcode opcode = AdapterOpcode::kMotionModulePower;
  std::uint32_t param = kSwitchOff;  ///< first parameter; the others are 0
  std::int64_t wait_after_ns = 0;    ///< pause after the reply, before the next step [ns]

  constexpr AdapterRequest request() const { return {.opcode = opcode, .params = {param, 0, 0, 0}, .payload = {}}; }
};

inline constexpr std::array<AdapterStep, 4> kStartImuSequence{{
    {AdapterOpcode::kMotionModuleActivate, kSwitchOff, 0},
    {AdapterOpcode::kMotionModulePower, kSwitchOff, 0},
    {AdapterOpcode::kMotionModulePower, kSwitchOn, kPowerUpToActivateWaitNs},
    {AdapterOpcode::kMotionModuleActivate, kSwitchOn, 0},
}};

inline constexpr std::array<AdapterStep, 2> kStopImuSequence{{
    {AdapterOpcode::kMotionModuleActivate, kSwitchOff, 0},
    {AdapterOpcode::kMotionModulePower, kSwitchOff, 0},
}};

}  // namespace vifusion::motion
