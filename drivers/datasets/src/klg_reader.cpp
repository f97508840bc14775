#include "vifusion/datasets/klg_reader.hpp"

#include <zlib.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <sstream>

#include "image_files.hpp"
#include "text_fields.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"

namespace vifusion::datasets {
namespace {

// The format is little-endian and read with memcpy; every supported target (x86-64, aarch64) is too.
static_assert(std::endian::native == std::endian::little, "KlgReader assumes a little-endian host");

constexpr std::uint64_t kFrameHeaderBytes = 8 + 4 + 4;

template <typename T>
T fromBytes(const std::uint8_t* bytes) {
  T value;
  std::memcpy(&value, bytes, sizeof(T));
  return value;
}

}  // namespace

KlgReader::KlgReader(const std::filesystem::path& path)
    : path_(path), name_(path.filename().string()), decoder_(std::make_unique<detail::ImageDecoder>()) {
  calibration_.camera = PinholeCamera::create(kWidth, kHeight, 528.0, 528.0, 320.0, 240.0);
  calibration_.depth_scale_m = 0.001;
  std::error_code ec;
  const std::uint64_t file_size = std::filesystem::file_size(path_, ec);
  if (ec) throw Error(name_ + ": cannot open file '" + path_.string() + "'");
  file_.open(path_, std::ios::binary);
  if (!file_) throw Error(name_ + ": cannot open file '" + path_.string() + "'");
  if (file_size < 4) throw Error(name_ + ": truncated: " + std::to_string(file_size) + " bytes, no frame count");

  std::uint8_t header[kFrameHeaderBytes];
  readAt(0, header, 4, "frame count");
  const std::int32_t frame_count = fromBytes<std::int32_t>(header);
  if (frame_count <= 0) throw Error(name_ + ": frame count is " + std::to_string(frame_count) + ", expected > 0");

  std::uint64_t offset = 4;
  for (std::int32_t k = 0; k < frame_count; ++k) {
    const std::string frame = name_ + " frame " + std::to_string(k) + ": ";
    // Each size is compared with the bytes actually left before anything is allocated or read, so a
    // corrupt size cannot trigger a huge allocation or a read past the end.
    if (file_size - offset < kFrameHeaderBytes) {
      throw Error(frame + "header runs past the end of the file (truncated log; " + std::to_string(file_size - offset) +
                  " bytes left, frame count says " + std::to_string(frame_count) + " frames)");
    }
    readAt(offset, header, kFrameHeaderBytes, "frame header");
    FrameRecord record;
    const std::int64_t t_us = fromBytes<std::int64_t>(header);
    record.depth_size = fromBytes<std::int32_t>(header + 8);
    record.image_size = fromBytes<std::int32_t>(header + 12);
    record.offset = offset + kFrameHeaderBytes;
    if (t_us < 0 || t_us > kMaxFileStampNs / kNsPerMicrosecond) {
      throw Error(frame + "timestamp " + std::to_string(t_us) + " us is out of range");
    }
    record.t_ns = t_us * kNsPerMicrosecond;
    if (record.depth_size <= 0) throw Error(frame + "depth size " + std::to_string(record.depth_size) + " must be > 0");
    if (record.image_size < 0) throw Error(frame + "image size " + std::to_string(record.image_size) + " is negative");
    const std::uint64_t left = file_size - record.offset;
    const std::uint64_t needed =
        static_cast<std::uint64_t>(record.depth_size) + static_cast<std::uint64_t>(record.image_size);
    if (needed > left) {
      throw Error(frame + "depth (" + std::to_string(record.depth_size) + " bytes) and image (" +
                  std::to_string(record.image_size) + " bytes) run past the end of the file (" + std::to_string(left) +
                  " bytes left; truncated log)");
    }
    if (!records_.empty()) detail::requireIncreasing(records_.back().t_ns, record.t_ns, frame);
    records_.push_back(record);
    offset = record.offset + needed;
  }
  if (offset != file_size) {
    throw Error(name_ + ": " + std::to_string(file_size - offset) + " bytes after the last of " +
                std::to_string(frame_count) + " frames (frame count does not match the data)");
  }
}

KlgReader::~KlgReader() = default;

void KlgReader::readAt(std::uint64_t offset, void* bytes, std::size_t size, const std::string& what) {
  file_.seekg(static_cast<std::streamoff>(offset));
  if (!file_.read(static_cast<char*>(bytes), static_cast<std::streamsize>(size))) {
    file_.clear();
    throw Error(name_ + ": cannot read " + what + " at byte " + std::to_string(offset));
  }
}

bool KlgReader::nextFrame(RgbdFrame& frame) {
  if (next_ >= records_.size()) return false;
  const std::size_t index = next_++;  // past it even when it cannot be read: the caller may skip it
  const FrameRecord& record = records_[index];
  const std::string what = "frame " + std::to_string(index);
  if (frame.depth.width() != kWidth || frame.depth.height() != kHeight) frame.depth.resize(kWidth, kHeight);
  if (frame.rgb.width() != kWidth || frame.rgb.height() != kHeight) frame.rgb.resize(kWidth, kHeight);

  if (record.depth_size == kRawDepthBytes) {
    readAt(record.offset, frame.depth.data(), kRawDepthBytes, what + " depth");
  } else {
    compressed_.resize(static_cast<std::size_t>(record.depth_size));
    readAt(record.offset, compressed_.data(), compressed_.size(), what + " depth");
    uLongf depth_bytes = kRawDepthBytes;
    const int status = uncompress(reinterpret_cast<Bytef*>(frame.depth.data()), &depth_bytes, compressed_.data(),
                                  static_cast<uLong>(compressed_.size()));
    if (status != Z_OK || depth_bytes != static_cast<uLongf>(kRawDepthBytes)) {
      throw Error(name_ + " " + what + ": zlib depth (" + std::to_string(record.depth_size) + " bytes) " +
                  (status == Z_OK ? "decompresses to " + std::to_string(depth_bytes) + " bytes, expected 614400"
                   : status == Z_BUF_ERROR ? "decompresses to more than 614400 bytes or is truncated"
                                           : "is corrupt (zlib error " + std::to_string(status) + ")"));
    }
  }

  const std::uint64_t image_offset = record.offset + static_cast<std::uint64_t>(record.depth_size);
  if (record.image_size == 0) {
    std::fill(frame.rgb.data(), frame.rgb.data() + frame.rgb.pixelCount(), Rgb8{});
  } else if (record.image_size == kRawImageBytes) {
    readAt(image_offset, frame.rgb.data(), kRawImageBytes, what + " image");
  } else {
    compressed_.resize(static_cast<std::size_t>(record.image_size));
    readAt(image_offset, compressed_.data(), compressed_.size(), what + " image");
    decoder_->decodeRgbOrder(compressed_, name_ + " " + what + " JPEG colour", kWidth, kHeight, frame.rgb);
  }
  frame.t_ns = record.t_ns;
  frame.index = static_cast<std::int64_t>(index);
  frame.depth_scale_m = calibration_.depth_scale_m;
  return true;
}

std::string KlgReader::describe() const {
  std::ostringstream out;
  out << "ElasticFusion log '" << path_.string() << "': " << records_.size()
      << " frames, 640x480, ElasticFusion default intrinsics 528/528/320/240, depth in mm, no IMU, no ground truth";
  return out.str();
}

}  // namespace vifusion::datasets
