#pragma once
// ElasticFusion / Kintinuous .klg logs (Logger1/Logger2, png_to_klg), little-endian:
//   int32 frame_count
//   per frame: int64 timestamp [µs], int32 depth_size, int32 image_size, depth bytes, image bytes
// depth: raw 640×480 uint16 millimetres if depth_size == 614400, else zlib-compressed;
// image: raw RGB888 if image_size == 921600, 0 → no colour (black), else JPEG.
// Logger2 hands its R,G,B buffer to OpenCV's JPEG encoder as if it were B,G,R, so decoding with
// OpenCV gives the R,G,B bytes back in memory order; both raw and JPEG colour are therefore taken as
// R,G,B without a swap (ElasticFusion's -f flag exists for logs written the other way).
//
// Every frame's sizes are checked against the file size when the log is opened, so a truncated or
// corrupt log is an error naming the frame before any frame is delivered. Calibration: the log holds
// none; ElasticFusion's defaults 640×480, 528/528/320/240, depth 1 mm per unit.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "vifusion/datasets/dataset_reader.hpp"

namespace vifusion::datasets {

namespace detail {
class ImageDecoder;
}  // namespace detail

class KlgReader final : public DatasetReader {
 public:
  static constexpr int kWidth = 640;
  static constexpr int kHeight = 480;
  static constexpr std::int32_t kRawDepthBytes = kWidth * kHeight * 2;  ///< 614400
  static constexpr std::int32_t kRawImageBytes = kWidth * kHeight * 3;  ///< 921600

  /// Reads the frame index and validates every size and stamp. @throws vifusion::Error naming the frame.
  explicit KlgReader(const std::filesystem::path& path);
  ~KlgReader() override;

  const RigCalibration& calibration() const override { return calibration_; }
  std::size_t frameCount() const override { return records_.size(); }
  std::optional<std::int64_t> listedFrameTimeNs(std::size_t index) const override {
    return index < records_.size() ? std::optional<std::int64_t>(records_[index].t_ns) : std::nullopt;
  }
  /// @throws vifusion::Error for corrupt zlib depth or JPEG colour, naming the frame.
  bool nextFrame(RgbdFrame& frame) override;
  bool rewind() override {
    next_ = 0;
    return true;
  }
  std::string describe() const override;

 private:
  struct FrameRecord {
    std::int64_t t_ns = 0;
    std::uint64_t offset = 0;  ///< file offset of the depth bytes
    std::int32_t depth_size = 0;
    std::int32_t image_size = 0;
  };

  void readAt(std::uint64_t offset, void* bytes, std::size_t size, const std::string& what);

  std::filesystem::path path_;
  std::string name_;  ///< file name, for errors
  std::ifstream file_;
  RigCalibration calibration_;
  std::vector<FrameRecord> records_;
  std::vector<std::uint8_t> compressed_;
  std::size_t next_ = 0;
  std::unique_ptr<detail::ImageDecoder> decoder_;
};

}  // namespace vifusion::datasets
