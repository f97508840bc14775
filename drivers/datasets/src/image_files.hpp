#pragma once
// Private: decoding the PNG/JPEG images of file-based datasets into RgbdFrame buffers with the checks
// every reader needs (missing, truncated, wrong type, wrong size). OpenCV stays out of public headers.

#include <cstdint>
#include <filesystem>
#include <opencv2/core/mat.hpp>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/image.hpp"

namespace vifusion::datasets::detail {

/// Throws "<prefix>missing file '<relative>'" unless root/relative is a regular file. Readers call it
/// for every file an index references when they open, so a gap surfaces before the run starts.
void requireFile(const std::filesystem::path& root, const std::string& relative, const std::string& prefix);

/// Decodes images into caller-owned buffers (reused when the size is unchanged); keeps its file-byte
/// buffer between calls.
class ImageDecoder {
 public:
  /// 16-bit single-channel PNG at root/relative into `depth`, which must come out width × height.
  /// @throws vifusion::Error naming `relative` (missing, truncated or not a PNG, wrong type, wrong size).
  void readDepthPng(const std::filesystem::path& root, const std::string& relative, int width, int height,
                    Image<std::uint16_t>& depth);

  /// 8-bit colour image (BGR or BGRA in the file's decoder order; alpha dropped) into `rgb`.
  void readColor(const std::filesystem::path& root, const std::string& relative, int width, int height,
                 Image<Rgb8>& rgb);

  /// Decodes in-memory compressed colour (JPEG/PNG) whose decoded byte order is already R, G, B
  /// (ElasticFusion logs, see klg_reader.hpp). `what` names the data in errors.
  void decodeRgbOrder(std::span<const std::uint8_t> bytes, const std::string& what, int width, int height,
                      Image<Rgb8>& rgb);

 private:
  void readBytes(const std::filesystem::path& root, const std::string& relative);
  void decode(std::span<const std::uint8_t> bytes, int flags, const std::string& what, const char* failure, int width,
              int height);
  void requireShape(const std::string& what, int width, int height) const;

  std::vector<std::uint8_t> bytes_;
  cv::Mat decoded_;
};

}  // namespace vifusion::datasets::detail
