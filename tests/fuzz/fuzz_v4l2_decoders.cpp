// libFuzzer target: the V4L2 frame decoders (drivers/v4l2 ds_metadata.hpp, yuyv.hpp, z16.hpp) on arbitrary
// frames with arbitrary sizes. The first kHeaderBytes choose the image size, the bytes per line, the output
// view's row padding and the DS4 node; the rest is the frame. Besides "no crash, no sanitizer report" it
// checks what the decoders promise:
//  - a true result wrote only inside the caller's image: the view sits in a larger buffer filled with a
//    sentinel, and every byte outside the view (guards and each row's padding) must still hold it;
//  - what they wrote is what the documented layouts say (Z16: little-endian copy; YUYV: BT.601 of each
//    pixel's Y with its pair's Cb/Cr; dinghy: the 16 little-endian words of the last row);
//  - the writers (fixtures of the scripted device) round-trip through the readers and touch only their bytes.
// Sizes are mostly small (so a conversion can succeed within -max_len) and sometimes any int32, so the
// size arithmetic is fuzzed at its limits too.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <optional>
#include <span>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/v4l2/ds_metadata.hpp"
#include "vifusion/v4l2/problem_text.hpp"
#include "vifusion/v4l2/yuyv.hpp"
#include "vifusion/v4l2/z16.hpp"

namespace {

using namespace vifusion;
using namespace vifusion::v4l2;

// Input header: [0] mode bits, [1..4] width, [5..8] height, [9..12] bytes per line (little-endian u32 each),
// [13] view row padding.
constexpr std::size_t kHeaderBytes = 14;
constexpr int kSmallSideSpan = 72;   // small sizes are raw % 72 − 4: −4 … 67, negatives and zero included
constexpr int kSmallSideOffset = 4;  // (67 px of YUYV is 134 B a row: several rows fit in -max_len)
constexpr int kMaxRowPadding = 7;    // view stride − width [px]
constexpr int kBytesPerPixel = 2;    // YUYV and Z16 alike
constexpr int kBytesPerLinePadSpan = 16;
constexpr std::size_t kGuardPixels = 64;
// A frame of at most 1010 bytes (the ctest's -max_len 1024 less the header) fills at most 505 pixels; with
// up to kMaxRowPadding pixels between rows such a view spans fewer than 505 + 7 · 504 < 4096 buffer pixels.
// A larger -max_len may need more (AddressSanitizer then reports the overflow of this buffer).
constexpr std::size_t kMaxViewPixels = 4096;
constexpr std::size_t kBufferPixels = kGuardPixels + kMaxViewPixels + kGuardPixels;
constexpr std::uint8_t kSentinelByte = 0xA7;
constexpr std::uint32_t kCounterFlip = 0xA5A5A5A5;  // a colour number different in every other bit

void require(bool condition) {
  if (!condition) __builtin_trap();
}

// The per-pixel checks are the oracle, not code under test: without coverage instrumentation (and not inlined
// into instrumented callers) their comparisons are not traced, which was most of a run's time.
#define VIFUSION_FUZZ_ORACLE __attribute__((no_sanitize("coverage"), noinline))

std::uint32_t loadLittleEndian32(const std::uint8_t* bytes) {
  return static_cast<std::uint32_t>(bytes[0]) | static_cast<std::uint32_t>(bytes[1]) << 8 |
         static_cast<std::uint32_t>(bytes[2]) << 16 | static_cast<std::uint32_t>(bytes[3]) << 24;
}

/// Mode 3 of two bits: the raw int32; otherwise a small size.
int pickSide(std::uint32_t raw, unsigned mode) {
  if (mode == 3) return static_cast<int>(raw);
  return static_cast<int>(raw % kSmallSideSpan) - kSmallSideOffset;
}

std::uint32_t pickBytesPerLine(std::uint32_t raw, unsigned mode, int width) {
  const std::int64_t tight = static_cast<std::int64_t>(std::max(width, 0)) * kBytesPerPixel;
  switch (mode) {
    case 0:
      return static_cast<std::uint32_t>(tight);
    case 1:
      return static_cast<std::uint32_t>(tight + raw % kBytesPerLinePadSpan);
    case 2:
      return static_cast<std::uint32_t>(std::max<std::int64_t>(0, tight - raw % kBytesPerLinePadSpan));
    default:
      return raw;
  }
}

struct Geometry {
  int width = 0;
  int height = 0;
  std::uint32_t bytes_per_line = 0;
  int row_padding = 0;
  DinghyNode node = DinghyNode::kDepth;
};

/// Pixels the view spans in the buffer, or nullopt when it is empty or does not fit in kMaxViewPixels.
std::optional<std::size_t> viewSpan(const Geometry& g) {
  if (g.width <= 0 || g.height <= 0) return std::nullopt;
  const std::int64_t span = (static_cast<std::int64_t>(g.width) + g.row_padding) * (g.height - 1) + g.width;
  if (span > static_cast<std::int64_t>(kMaxViewPixels)) return std::nullopt;
  return static_cast<std::size_t>(span);
}

/// kBufferPixels of the widest pixel type, all kSentinelByte: what an untouched stretch compares equal to.
const std::uint8_t* sentinelBlock() {
  static const auto block = [] {
    std::array<std::uint8_t, kBufferPixels * sizeof(Rgb8)> bytes;
    bytes.fill(kSentinelByte);
    return bytes;
  }();
  return block.data();
}

/// Fills `buffer` with the sentinel. memset, not fill(): libFuzzer's comparison tracing on every element of
/// a fill() loop made it most of a run's time.
template <typename T>
void fillSentinel(std::array<T, kBufferPixels>& buffer) {
  std::memset(buffer.data(), kSentinelByte, sizeof(buffer));
}

/// True when pixels [begin, end) of `buffer` still hold the sentinel.
template <typename T>
bool untouched(const std::array<T, kBufferPixels>& buffer, std::size_t begin, std::size_t end) {
  return begin >= end || std::memcmp(buffer.data() + begin, sentinelBlock(), (end - begin) * sizeof(T)) == 0;
}

/// True when every pixel of `buffer` outside the view (guards, each row's padding) still holds the sentinel.
template <typename T>
bool untouchedOutsideView(const std::array<T, kBufferPixels>& buffer, const Geometry& g) {
  const std::size_t stride = static_cast<std::size_t>(g.width + g.row_padding);
  const std::size_t width = static_cast<std::size_t>(g.width);
  std::size_t row_start = kGuardPixels;
  if (!untouched(buffer, 0, row_start)) return false;
  for (int y = 0; y < g.height; ++y, row_start += stride) {
    if (!untouched(buffer, row_start + width, row_start + stride)) return false;
  }
  return untouched(buffer, row_start, kBufferPixels);
}

/// The view into `buffer` for `g` (any size; a decoder must refuse the ones the frame cannot fill).
template <typename T>
ImageView<T> viewInto(std::array<T, kBufferPixels>& buffer, const Geometry& g) {
  const std::ptrdiff_t stride = static_cast<std::ptrdiff_t>(g.width) + g.row_padding;
  return ImageView<T>(buffer.data() + kGuardPixels, g.width, g.height, stride > 0 ? stride : 1);
}

/// Z16: each pixel is the little-endian u16 at its place in the frame.
VIFUSION_FUZZ_ORACLE bool depthMatchesFrame(const std::array<std::uint16_t, kBufferPixels>& depth,
                                            std::span<const std::uint8_t> frame, const Geometry& g) {
  const std::size_t stride = static_cast<std::size_t>(g.width + g.row_padding);
  for (int y = 0; y < g.height; ++y) {
    for (int x = 0; x < g.width; ++x) {
      const std::size_t at = static_cast<std::size_t>(g.bytes_per_line) * static_cast<std::size_t>(y) +
                             static_cast<std::size_t>(x) * kBytesPerPixel;
      const auto expected = static_cast<std::uint16_t>(frame[at] | frame[at + 1] << 8);
      if (depth[kGuardPixels + stride * static_cast<std::size_t>(y) + static_cast<std::size_t>(x)] != expected) {
        return false;
      }
    }
  }
  return true;
}

/// YUYV: each pixel is BT.601 of its own Y and its pair's Cb, Cr (memory order Y0 Cb Y1 Cr).
VIFUSION_FUZZ_ORACLE bool rgbMatchesFrame(const std::array<Rgb8, kBufferPixels>& rgb,
                                          std::span<const std::uint8_t> frame, const Geometry& g) {
  const std::size_t stride = static_cast<std::size_t>(g.width + g.row_padding);
  for (int y = 0; y < g.height; ++y) {
    const std::uint8_t* row = frame.data() + static_cast<std::size_t>(g.bytes_per_line) * static_cast<std::size_t>(y);
    for (int x = 0; x < g.width; ++x) {
      const std::uint8_t* pair = row + static_cast<std::size_t>(x / 2) * 2 * kBytesPerPixel;
      const Rgb8 expected = bt601LimitedToRgb(pair[x % 2 == 0 ? 0 : 2], pair[1], pair[3]);
      if (!(rgb[kGuardPixels + stride * static_cast<std::size_t>(y) + static_cast<std::size_t>(x)] == expected)) {
        return false;
      }
    }
  }
  return true;
}

/// True when `a` and `b` (same size) agree outside bytes [begin, end).
bool sameOutside(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b, std::size_t begin, std::size_t end) {
  return std::memcmp(a.data(), b.data(), begin) == 0 &&
         std::memcmp(a.data() + end, b.data() + end, a.size() - end) == 0;
}

void fuzzZ16(std::span<const std::uint8_t> frame, const Geometry& g) {
  static std::array<std::uint16_t, kBufferPixels> depth;
  fillSentinel(depth);
  ProblemText problem;
  if (!z16ToDepth(frame, g.bytes_per_line, viewInto(depth, g), problem)) {
    require(!problem.empty());
    return;
  }
  require(viewSpan(g).has_value());
  require(untouchedOutsideView(depth, g));
  require(depthMatchesFrame(depth, frame, g));
}

void fuzzYuyv(std::span<const std::uint8_t> frame, const Geometry& g) {
  static std::array<Rgb8, kBufferPixels> rgb;
  fillSentinel(rgb);
  ProblemText problem;
  if (!yuyvToRgb(frame, g.bytes_per_line, viewInto(rgb, g), problem)) {
    require(!problem.empty());
    return;
  }
  require(viewSpan(g).has_value() && g.width % 2 == 0);
  require(untouchedOutsideView(rgb, g));
  require(rgbMatchesFrame(rgb, frame, g));
}

void fuzzDinghy(std::span<const std::uint8_t> frame, const Geometry& g) {
  ProblemText problem;
  const std::optional<Dinghy> dinghy = readDinghy(frame, g.bytes_per_line, g.height, problem);
  // The writer on an exact-size copy (AddressSanitizer sees a write past its end) must agree on the fit.
  std::vector<std::uint8_t> copy(frame.begin(), frame.end());
  Dinghy written;
  written.magic = g.node == DinghyNode::kDepth ? kDinghyMagicDepth : kDinghyMagicInfrared;
  written.frame_counter = static_cast<std::uint32_t>(frame.size());
  written.cam_module_status = g.bytes_per_line;
  const bool wrote = writeDinghy(written, copy, g.bytes_per_line, g.height);
  require(wrote == dinghy.has_value());
  if (!dinghy) {
    require(!problem.empty());
    return;
  }
  const std::size_t offset = static_cast<std::size_t>(g.bytes_per_line) * static_cast<std::size_t>(g.height - 1);
  require(g.height >= 1 && offset + kDinghyBytes <= frame.size());
  const std::uint8_t* row = frame.data() + offset;
  require(dinghy->magic == loadLittleEndian32(row) && dinghy->frame_counter == loadLittleEndian32(row + 4));
  require(dinghy->frame_status == loadLittleEndian32(row + 8));
  require(dinghy->cam_module_status == loadLittleEndian32(row + 36));
  require(dinghy->vdf_error_status == loadLittleEndian32(row + 56));

  problem.clear();
  const bool good = checkDinghy(*dinghy, g.node, problem);
  const std::uint32_t magic = g.node == DinghyNode::kDepth ? kDinghyMagicDepth : kDinghyMagicInfrared;
  const bool expected_good = dinghy->magic == magic && dinghy->frame_status == 0 && dinghy->vdf_error_status == 0 &&
                             (g.node == DinghyNode::kDepth || dinghy->cam_module_status == 0);
  require(good == expected_good && good == problem.empty());

  // Round trip, and nothing outside the metadata row changed.
  ProblemText reread_problem;
  const std::optional<Dinghy> reread = readDinghy(copy, g.bytes_per_line, g.height, reread_problem);
  require(reread.has_value() && reread->magic == written.magic && reread->frame_counter == written.frame_counter &&
          reread->cam_module_status == written.cam_module_status && reread->frame_status == 0);
  require(sameOutside(copy, frame, offset, offset + kDinghyBytes));
}

void fuzzColourNumber(std::span<const std::uint8_t> frame, const Geometry& g) {
  ProblemText problem;
  const std::optional<std::uint32_t> number =
      readColourFrameNumber(frame, g.bytes_per_line, g.width, g.height, problem);
  std::vector<std::uint8_t> copy(frame.begin(), frame.end());
  const std::uint32_t flipped = number.value_or(0) ^ kCounterFlip;
  const bool wrote = writeColourFrameNumber(flipped, copy, g.bytes_per_line, g.width, g.height);
  require(wrote == number.has_value());
  if (!number) {
    require(!problem.empty());
    return;
  }
  ProblemText reread_problem;
  require(readColourFrameNumber(copy, g.bytes_per_line, g.width, g.height, reread_problem) == flipped);
  // Only the least significant bits of luma bytes in the last row's final kColourCounterPixels pixels change.
  const std::size_t row_end = static_cast<std::size_t>(g.bytes_per_line) * static_cast<std::size_t>(g.height - 1) +
                              static_cast<std::size_t>(g.width) * kBytesPerPixel;
  const std::size_t first = row_end - static_cast<std::size_t>(kColourCounterPixels) * kBytesPerPixel;
  require(sameOutside(copy, frame, first, row_end));
  for (std::size_t i = first; i < row_end; ++i) {
    const bool luma = (i - first) % kBytesPerPixel == 0;
    require((copy[i] & ~1u) == (frame[i] & ~1u) && (luma || copy[i] == frame[i]));
  }
  // The rate correction is total: any fps pair, no division by zero.
  static_cast<void>(colourFrameNumber(*number, g.width, g.height));
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < kHeaderBytes) return 0;
  const std::uint8_t modes = data[0];
  Geometry g;
  g.width = pickSide(loadLittleEndian32(data + 1), modes & 3u);
  g.height = pickSide(loadLittleEndian32(data + 5), (modes >> 2) & 3u);
  g.bytes_per_line = pickBytesPerLine(loadLittleEndian32(data + 9), (modes >> 4) & 3u, g.width);
  g.row_padding = data[13] % (kMaxRowPadding + 1);
  g.node = (modes & 0x40u) != 0 ? DinghyNode::kInfrared : DinghyNode::kDepth;
  const std::span<const std::uint8_t> frame(data + kHeaderBytes, size - kHeaderBytes);

  fuzzZ16(frame, g);
  fuzzYuyv(frame, g);
  fuzzDinghy(frame, g);
  fuzzColourNumber(frame, g);
  return 0;
}
