#pragma once
// A scripted ZR300-like camera for the V4L2 tests: a depth node (Z16 628×469 with the dinghy row), a colour
// node (YUYV with the frame number in the last 32 pixels) and an IR node carrying the DS4 XU controls. Frame
// content is a function of the absolute frame index k, so a test can regenerate what it must receive. The
// producers write into the buffer only (no allocation), as a real driver's DMA would.

#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "vifusion/v4l2/ds_metadata.hpp"
#include "vifusion/v4l2/fourcc.hpp"
#include "vifusion/v4l2_scripted/scripted_v4l2_device.hpp"

namespace vifusion::v4l2::test {

using v4l2_scripted::ScriptedFrame;
using v4l2_scripted::ScriptedFrameRequest;

inline constexpr const char* kDepthPath = "/dev/video1";
inline constexpr const char* kColourPath = "/dev/video2";
inline constexpr const char* kInfraredPath = "/dev/video0";
inline constexpr int kDepthWidthPx = 628;
inline constexpr int kDepthHeightPx = 469;  // 468 depth rows + the dinghy row
inline constexpr int kColourWidthPx = 640;
inline constexpr int kColourHeightPx = 480;
inline constexpr std::int64_t kPeriodNs = 33'333'333;  // 30 Hz schedule
/// The first frame arrives this long after the clock's start, so a stream started at once gets frame 0.
inline constexpr std::int64_t kFirstArrivalDelayNs = 10'000'000;
/// Kernel stamp ≈ arrival − this (start of exposure precedes completion on the host).
inline constexpr std::int64_t kStampBeforeArrivalNs = 25'000'000;
/// The kernel stamp scripted for a frame completing at arrival_ns: whole µs, as V4L2 reports them, so the
/// stamp comes out of the driver exactly as scripted.
inline std::int64_t scriptedStampNs(std::int64_t arrival_ns) {
  return (arrival_ns - kStampBeforeArrivalNs) / 1000 * 1000;
}
/// Arrival of frame k on the fixture's schedule.
inline std::int64_t arrivalNs(std::int64_t k) {
  return v4l2_scripted::ManualClock::kDefaultStartNs + kFirstArrivalDelayNs + k * kPeriodNs;
}

/// The first embedded counter the camera reports (it does not start at zero).
inline constexpr std::uint32_t kFirstDinghyCounter = 1000;

/// Depth value of pixel (x, y) in frame k: every pixel and every frame differ, the high byte included.
inline std::uint16_t depthValue(std::int64_t k, int x, int y) {
  return static_cast<std::uint16_t>(k * 131 + x * 7 + y * 509);
}

inline void fillDepth(std::int64_t k, std::uint32_t counter, std::span<std::uint8_t> frame,
                      std::uint32_t bytes_per_line) {
  for (int y = 0; y < kDepthHeightPx - 1; ++y) {
    std::uint8_t* row = frame.data() + static_cast<std::size_t>(y) * bytes_per_line;
    for (int x = 0; x < kDepthWidthPx; ++x) {
      const std::uint16_t value = depthValue(k, x, y);
      row[2 * x] = static_cast<std::uint8_t>(value & 0xFF);
      row[2 * x + 1] = static_cast<std::uint8_t>(value >> 8);
    }
  }
  Dinghy dinghy;
  dinghy.magic = kDinghyMagicDepth;
  dinghy.frame_counter = counter;
  writeDinghy(dinghy, frame, bytes_per_line, kDepthHeightPx);
}

/// Colour byte i of frame k before the frame number is written.
inline std::uint8_t colourByte(std::int64_t k, std::size_t i) { return static_cast<std::uint8_t>(k * 17 + i * 3); }

inline void fillColour(std::int64_t k, std::uint32_t number, std::span<std::uint8_t> frame,
                       std::uint32_t bytes_per_line, int width_px, int height_px) {
  for (std::size_t i = 0; i < frame.size(); ++i) frame[i] = colourByte(k, i);
  writeColourFrameNumber(number, frame, bytes_per_line, width_px, height_px);
}

/// Depth node offering the DS4 depth modes; `produce` defaults to the plain depth script.
inline v4l2_scripted::ScriptedNodeConfig depthNodeConfig(v4l2_scripted::FrameProducer produce = {}) {
  v4l2_scripted::ScriptedNodeConfig config;
  config.path = kDepthPath;
  config.formats = {{kFourccZ16, kDepthWidthPx, kDepthHeightPx, 0, {30, 60, 90}},
                    {kFourccZ16, 628, 361, 0, {30, 60, 90}},
                    {kFourccZ16, 628, 242, 0, {30, 60, 90}}};
  config.schedule.first_arrival_ns = v4l2_scripted::ManualClock::kDefaultStartNs + kFirstArrivalDelayNs;
  config.schedule.period_ns = kPeriodNs;
  config.schedule.produce =
      produce ? std::move(produce) : [](const ScriptedFrameRequest& request, ScriptedFrame& frame) {
        fillDepth(request.frame_index, kFirstDinghyCounter + static_cast<std::uint32_t>(request.frame_index),
                  request.payload, request.format.bytesperline);
        frame.t_stamp_ns = scriptedStampNs(request.arrival_ns);
      };
  return config;
}

/// Colour node as an unpatched-or-patched uvcvideo exposes it: YUYV only.
inline v4l2_scripted::ScriptedNodeConfig colourNodeConfig(v4l2_scripted::FrameProducer produce = {}) {
  v4l2_scripted::ScriptedNodeConfig config;
  config.path = kColourPath;
  config.formats = {{kFourccYuyv, kColourWidthPx, kColourHeightPx, 0, {30, 60}},
                    {kFourccYuyv, 320, 240, 0, {30, 60}},
                    {kFourccYuyv, 1920, 1080, 0, {15, 30}}};
  config.schedule.first_arrival_ns = v4l2_scripted::ManualClock::kDefaultStartNs + kFirstArrivalDelayNs;
  config.schedule.period_ns = kPeriodNs;
  config.schedule.produce =
      produce ? std::move(produce) : [](const ScriptedFrameRequest& request, ScriptedFrame& frame) {
        fillColour(request.frame_index, static_cast<std::uint32_t>(request.frame_index), request.payload,
                   request.format.bytesperline, static_cast<int>(request.format.width),
                   static_cast<int>(request.format.height));
        frame.t_stamp_ns = scriptedStampNs(request.arrival_ns);
      };
  return config;
}

/// IR node: carries the DS4 XU (unit 2) with stream intent, depth units (1000 µm) and emitter.
inline v4l2_scripted::ScriptedNodeConfig infraredNodeConfig() {
  v4l2_scripted::ScriptedNodeConfig config;
  config.path = kInfraredPath;
  config.formats = {{kFourccGrey, 640, 481, 0, {30, 60, 90}}};
  config.schedule.produce = [](const ScriptedFrameRequest&, ScriptedFrame&) {};
  config.controls = {{2, 3, {0}, true}, {2, 4, {0xE8, 0x03, 0x00, 0x00}, true}, {2, 8, {0}, true}};
  return config;
}

}  // namespace vifusion::v4l2::test
