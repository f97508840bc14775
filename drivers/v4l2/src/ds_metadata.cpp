#include "vifusion/v4l2/ds_metadata.hpp"

#include <cstddef>

namespace vifusion::v4l2 {
namespace {

constexpr int kBitsPerByte = 8;
constexpr int kBytesPerWord = 4;
constexpr int kYuyvBytesPerPixel = 2;

// Word positions in the dinghy (ds-private.h order).
enum DinghyWord : int {
  kMagic = 0,
  kFrameCounter = 1,
  kFrameStatus = 2,
  kExposureLeftSum = 3,
  kExposureLeftDarkCount = 4,
  kExposureLeftBrightCount = 5,
  kExposureRightSum = 6,
  kExposureRightDarkCount = 7,
  kExposureRightBrightCount = 8,
  kCamModuleStatus = 9,
  kVdfErrorStatus = 14,
};

std::uint32_t loadLittleEndian32(const std::uint8_t* bytes) {
  std::uint32_t value = 0;
  for (int i = kBytesPerWord - 1; i >= 0; --i) value = (value << kBitsPerByte) | bytes[i];
  return value;
}

void storeLittleEndian32(std::uint32_t value, std::uint8_t* bytes) {
  for (int i = 0; i < kBytesPerWord; ++i) bytes[i] = static_cast<std::uint8_t>(value >> (kBitsPerByte * i));
}

/// Bit of the frame number carried by counter pixel i (0 … 31), see the header.
int colourCounterBit(int pixel) {
  constexpr int kTopBitOfOddPixels = 32;
  constexpr int kTopBitOfEvenPixels = 30;
  return (pixel % 2 == 1) ? kTopBitOfOddPixels - pixel : kTopBitOfEvenPixels - pixel;
}

std::size_t lastRowOffset(std::uint32_t bytes_per_line, int height_rows) {
  return static_cast<std::size_t>(bytes_per_line) * static_cast<std::size_t>(height_rows - 1);
}

/// Offset of the first counter pixel's luma byte, or nullopt when the frame cannot hold the counter.
std::optional<std::size_t> colourCounterOffset(std::size_t frame_bytes, std::uint32_t bytes_per_line, int width_px,
                                               int height_px) {
  if (width_px < kColourCounterPixels || height_px < 1) return std::nullopt;
  // In size_t: width_px × 2 overflows int for widths above 2³⁰ (a corrupt or hostile size).
  const std::size_t row_bytes = static_cast<std::size_t>(width_px) * kYuyvBytesPerPixel;
  if (bytes_per_line < row_bytes) return std::nullopt;
  const std::size_t row_end = lastRowOffset(bytes_per_line, height_px) + row_bytes;
  if (frame_bytes < row_end) return std::nullopt;
  return row_end - static_cast<std::size_t>(kColourCounterPixels) * kYuyvBytesPerPixel;
}

}  // namespace

std::optional<Dinghy> readDinghy(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line, int height_rows,
                                 ProblemText& problem) {
  const std::size_t offset = height_rows >= 1 ? lastRowOffset(bytes_per_line, height_rows) : 0;
  if (height_rows < 1 || bytes_per_line < static_cast<std::uint32_t>(kDinghyBytes) ||
      frame.size() < offset + kDinghyBytes) {
    problem.set("dinghy: frame of %zu bytes (%d rows of %u bytes) cannot hold the %d-byte metadata row", frame.size(),
                height_rows, bytes_per_line, kDinghyBytes);
    return std::nullopt;
  }
  const std::uint8_t* row = frame.data() + offset;
  const auto word = [row](int index) { return loadLittleEndian32(row + index * kBytesPerWord); };
  Dinghy dinghy;
  dinghy.magic = word(kMagic);
  dinghy.frame_counter = word(kFrameCounter);
  dinghy.frame_status = word(kFrameStatus);
  dinghy.exposure_left_sum = word(kExposureLeftSum);
  dinghy.exposure_left_dark_count = word(kExposureLeftDarkCount);
  dinghy.exposure_left_bright_count = word(kExposureLeftBrightCount);
  dinghy.exposure_right_sum = word(kExposureRightSum);
  dinghy.exposure_right_dark_count = word(kExposureRightDarkCount);
  dinghy.exposure_right_bright_count = word(kExposureRightBrightCount);
  dinghy.cam_module_status = word(kCamModuleStatus);
  dinghy.vdf_error_status = word(kVdfErrorStatus);
  return dinghy;
}

bool checkDinghy(const Dinghy& dinghy, DinghyNode node, ProblemText& problem) {
  const bool infrared = node == DinghyNode::kInfrared;
  const char* name = infrared ? "infrared" : "depth";
  const std::uint32_t expected_magic = infrared ? kDinghyMagicInfrared : kDinghyMagicDepth;
  if (dinghy.magic != expected_magic) {
    problem.set("%s dinghy magic 0x%08x, expected 0x%08x (frame %u)", name, dinghy.magic, expected_magic,
                dinghy.frame_counter);
    return false;
  }
  if (dinghy.frame_status != 0) {
    problem.set("%s dinghy frame status 0x%08x, expected 0 (frame %u)", name, dinghy.frame_status,
                dinghy.frame_counter);
    return false;
  }
  if (dinghy.vdf_error_status != 0) {
    problem.set("%s dinghy VDF error status 0x%08x, expected 0 (frame %u)", name, dinghy.vdf_error_status,
                dinghy.frame_counter);
    return false;
  }
  if (infrared && dinghy.cam_module_status != 0) {
    problem.set("%s dinghy CAM-module status 0x%08x, expected 0 (frame %u)", name, dinghy.cam_module_status,
                dinghy.frame_counter);
    return false;
  }
  return true;
}

bool writeDinghy(const Dinghy& dinghy, std::span<std::uint8_t> frame, std::uint32_t bytes_per_line, int height_rows) {
  if (height_rows < 1 || bytes_per_line < static_cast<std::uint32_t>(kDinghyBytes) ||
      frame.size() < lastRowOffset(bytes_per_line, height_rows) + kDinghyBytes) {
    return false;
  }
  std::uint8_t* row = frame.data() + lastRowOffset(bytes_per_line, height_rows);
  const auto put = [row](int index, std::uint32_t value) { storeLittleEndian32(value, row + index * kBytesPerWord); };
  for (int i = 0; i < kDinghyWords; ++i) put(i, 0);  // pad words are zero
  put(kMagic, dinghy.magic);
  put(kFrameCounter, dinghy.frame_counter);
  put(kFrameStatus, dinghy.frame_status);
  put(kExposureLeftSum, dinghy.exposure_left_sum);
  put(kExposureLeftDarkCount, dinghy.exposure_left_dark_count);
  put(kExposureLeftBrightCount, dinghy.exposure_left_bright_count);
  put(kExposureRightSum, dinghy.exposure_right_sum);
  put(kExposureRightDarkCount, dinghy.exposure_right_dark_count);
  put(kExposureRightBrightCount, dinghy.exposure_right_bright_count);
  put(kCamModuleStatus, dinghy.cam_module_status);
  put(kVdfErrorStatus, dinghy.vdf_error_status);
  return true;
}

std::optional<std::uint32_t> readColourFrameNumber(std::span<const std::uint8_t> frame, std::uint32_t bytes_per_line,
                                                   int width_px, int height_px, ProblemText& problem) {
  const auto offset = colourCounterOffset(frame.size(), bytes_per_line, width_px, height_px);
  if (!offset) {
    problem.set("colour frame number: frame of %zu bytes (%dx%d, %u bytes per line) cannot hold the %d counter pixels",
                frame.size(), width_px, height_px, bytes_per_line, kColourCounterPixels);
    return std::nullopt;
  }
  std::uint32_t number = 0;
  for (int pixel = 0; pixel < kColourCounterPixels; ++pixel) {
    const std::uint32_t bit = frame[*offset + static_cast<std::size_t>(pixel) * kYuyvBytesPerPixel] & 1u;
    number |= bit << colourCounterBit(pixel);
  }
  return number;
}

bool writeColourFrameNumber(std::uint32_t number, std::span<std::uint8_t> frame, std::uint32_t bytes_per_line,
                            int width_px, int height_px) {
  const auto offset = colourCounterOffset(frame.size(), bytes_per_line, width_px, height_px);
  if (!offset) return false;
  for (int pixel = 0; pixel < kColourCounterPixels; ++pixel) {
    std::uint8_t& luma = frame[*offset + static_cast<std::size_t>(pixel) * kYuyvBytesPerPixel];
    const auto bit = static_cast<std::uint8_t>((number >> colourCounterBit(pixel)) & 1u);
    luma = static_cast<std::uint8_t>((luma & ~1u) | bit);
  }
  return true;
}

std::uint32_t colourFrameNumber(std::uint32_t raw_number, int depth_fps, int colour_fps) {
  if (colour_fps <= 0 || depth_fps <= colour_fps) return raw_number;
  return raw_number / static_cast<std::uint32_t>(depth_fps / colour_fps);
}

}  // namespace vifusion::v4l2
