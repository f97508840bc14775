#pragma once
// Metadata the ZR300/R200 (DS4 ASIC) camera writes into its own images, decoded from bytes.
//
// ESTABLISHED (librealsense legacy v1.12.x, src/ds-device.cpp dinghy_timestamp_reader / color_timestamp_reader
// and the `dinghy` struct in src/ds-private.h; read, not copied):
//  - IR (Y8/Y16/…) and depth (Z16) frames end with one extra row, the "dinghy": the frame the node delivers is
//    one row taller than the image (depth 628×469 = 468 image rows + dinghy; IR 640×481). The dinghy starts
//    at the first byte of that last row and is 16 packed 32-bit words: magic, frame counter, frame status,
//    exposure left sum / dark count / bright count, exposure right sum / dark count / bright count, CAM-module
//    status, 4 pad words, VDF error status, 1 pad word.
//  - Magic 0x08070605 on the IR node (subdevice 0), 0x04030201 on the depth node (subdevice 1).
//  - A frame is rejected when the magic is wrong, the frame status is non-zero, the VDF error status is
//    non-zero, or (IR only) the CAM-module status is non-zero.
//  - YUY2 colour frames carry a 32-bit frame number in the least significant bit of the first byte (the
//    luma byte) of each of the last 32 pixels. Pixel i of those 32 holds bit 30 − i for even i and bit
//    32 − i for odd i, so pixels (0, 1) hold bits (30, 31), (2, 3) hold (28, 29), …, (30, 31) hold (0, 1).
//  - When depth or IR runs faster than colour, the colour number counts depth frames: librealsense divides
//    it by depth fps / colour fps (its comment: "it seems"; see colourFrameNumber below).
//  - Depth images are padded by 6 px on every side to the 640×480 / 480×360 / 320×240 sizes users see
//    (subdevice mode pad/crop +6): put a Z16 image into the centre of a zeroed image (z16.hpp).
// ASSUMED (not stated by the source, which reinterprets the bytes in place on little-endian hosts):
//  - The words are little-endian (the camera and every host librealsense ran on are); the row starts at
//    bytes_per_line × (height − 1) (librealsense computes it for tightly packed rows, where both agree).
//  - What the individual status bits mean (undocumented); we only test for zero.
//  - Colour: librealsense rejects a number of 0 on the first frames (firmware not counting yet) and skips
//    the number for colour wider than 640 px ("HD formats seem to not include" it). Both are left to the
//    caller; they do not change how the bits are read.

#include <cstdint>
#include <optional>
#include <span>

#include "vifusion/v4l2/problem_text.hpp"

namespace vifusion::v4l2 {

inline constexpr std::uint32_t kDinghyMagicInfrared = 0x08070605;
inline constexpr std::uint32_t kDinghyMagicDepth = 0x04030201;
inline constexpr int kDinghyWords = 16;
inline constexpr int kDinghyBytes = kDinghyWords * 4;
/// Pixels at the end of a YUY2 frame that carry the colour frame number, one bit each.
inline constexpr int kColourCounterPixels = 32;

/// Which DS4 node a dinghy came from (they differ in magic and in which statuses count).
enum class DinghyNode { kInfrared, kDepth };

struct Dinghy {
  std::uint32_t magic = 0;
  std::uint32_t frame_counter = 0;  ///< +1 per frame the camera made; gaps are frames lost before the host
  std::uint32_t frame_status = 0;   ///< 0 = good
  std::uint32_t exposure_left_sum = 0;
  std::uint32_t exposure_left_dark_count = 0;
  std::uint32_t exposure_left_bright_count = 0;
  std::uint32_t exposure_right_sum = 0;
  std::uint32_t exposure_right_dark_count = 0;
  std::uint32_t exposure_right_bright_count = 0;
  std::uint32_t cam_module_status = 0;  ///< 0 = good (checked for IR only)
  std::uint32_t vdf_error_status = 0;   ///< 0 = good
};

/// The dinghy of a frame `height_rows` rows tall (dinghy row included) with rows `bytes_per_line` apart, or
/// nullopt (and `problem` set) when the frame is too short to hold it.
std::optional<Dinghy> readDinghy(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line, int height_rows,
                                 ProblemText& problem);
/// True when the camera marked the frame good; otherwise `problem` names the field, its value and what
/// was expected, e.g. "depth dinghy magic 0x12345678, expected 0x04030201".
bool checkDinghy(const Dinghy& dinghy, DinghyNode node, ProblemText& problem);
/// Writes `dinghy` into the last row (fixtures, the scripted device); false (nothing written) when the frame
/// cannot hold it.
bool writeDinghy(const Dinghy& dinghy, std::span<std::uint8_t> frame, std::uint32_t bytes_per_line, int height_rows);

/// The raw colour frame number of a YUYV frame, or nullopt (and `problem` set) when the frame is shorter
/// than its size says or a row has fewer than kColourCounterPixels pixels.
std::optional<std::uint32_t> readColourFrameNumber(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line,
                                                   int width_px, int height_px, ProblemText& problem);
/// Sets the counter bits of the last 32 pixels to `number`, leaving their other bits alone; false (nothing
/// written) when the frame cannot hold them.
bool writeColourFrameNumber(std::uint32_t number, std::span<std::uint8_t> frame, std::uint32_t bytes_per_line,
                            int width_px, int height_px);
/// The raw number in colour frames: divided by depth_fps / colour_fps when depth (or IR) streams faster
/// (integer ratio, as librealsense; 0 or a slower depth_fps means no depth stream: unchanged).
std::uint32_t colourFrameNumber(std::uint32_t raw_number, int depth_fps, int colour_fps);

}  // namespace vifusion::v4l2
