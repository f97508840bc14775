#include "image_files.hpp"

#include <cstring>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>

#include "encoded_image_size.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::datasets::detail {
namespace {

std::string describeType(int type) {
  const int depth = CV_MAT_DEPTH(type);
  const char* bits = depth == CV_8U || depth == CV_8S     ? "8-bit"
                     : depth == CV_16U || depth == CV_16S ? "16-bit"
                                                          : "float";
  return std::string(bits) + " " + std::to_string(CV_MAT_CN(type)) + "-channel";
}

}  // namespace

void requireFile(const std::filesystem::path& root, const std::string& relative, const std::string& prefix) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(root / relative, ec)) throw Error(prefix + "missing file '" + relative + "'");
}

void ImageDecoder::readBytes(const std::filesystem::path& root, const std::string& relative) {
  std::ifstream file(root / relative, std::ios::binary | std::ios::ate);
  if (!file) throw Error(relative + ": missing or unreadable");
  const std::streamoff size = file.tellg();
  if (size < 0) throw Error(relative + ": cannot read");
  bytes_.resize(static_cast<std::size_t>(size));
  file.seekg(0);
  if (!file.read(reinterpret_cast<char*>(bytes_.data()), size)) throw Error(relative + ": cannot read");
}

void ImageDecoder::decode(std::span<const std::uint8_t> bytes, int flags, const std::string& what, const char* failure,
                          int width, int height) {
  // The header's size is checked before OpenCV allocates the image (encoded_image_size.hpp).
  const std::optional<EncodedImageSize> size = encodedImageSize(bytes);
  if (!size) throw Error(what + ": " + failure + " (no PNG or JPEG header)");
  if (size->width != static_cast<std::uint32_t>(width) || size->height != static_cast<std::uint32_t>(height)) {
    throw Error(what + ": image is " + std::to_string(size->width) + "x" + std::to_string(size->height) +
                ", expected " + std::to_string(width) + "x" + std::to_string(height));
  }
  // OpenCV throws cv::Exception for some malformed inputs and returns an empty Mat for others
  // (a truncated PNG); both become the same boundary error.
  // imdecode leaves its destination untouched when it fails, so a kept buffer would hand back the
  // previous image for a truncated file; start each decode from an empty Mat.
  decoded_.release();
  try {
    if (bytes.empty()) throw Error(what + ": " + failure);
    const cv::Mat encoded(1, static_cast<int>(bytes.size()), CV_8UC1, const_cast<std::uint8_t*>(bytes.data()));
    cv::imdecode(encoded, flags, &decoded_);
  } catch (const cv::Exception& e) {
    throw Error(what + ": " + failure + " (" + e.what() + ")");
  }
  if (decoded_.empty()) throw Error(what + ": " + failure);
}

void ImageDecoder::requireShape(const std::string& what, int width, int height) const {
  if (decoded_.cols != width || decoded_.rows != height) {
    throw Error(what + ": image is " + std::to_string(decoded_.cols) + "x" + std::to_string(decoded_.rows) +
                ", expected " + std::to_string(width) + "x" + std::to_string(height));
  }
}

void ImageDecoder::readDepthPng(const std::filesystem::path& root, const std::string& relative, int width, int height,
                                Image<std::uint16_t>& depth) {
  readBytes(root, relative);
  decode(bytes_, cv::IMREAD_UNCHANGED, relative, "truncated or not a PNG", width, height);
  if (decoded_.type() != CV_16UC1) {
    throw Error(relative + ": depth must be a 16-bit 1-channel image, found " + describeType(decoded_.type()));
  }
  requireShape(relative, width, height);
  if (depth.width() != width || depth.height() != height) depth.resize(width, height);
  for (int y = 0; y < height; ++y) {
    std::memcpy(depth.view().row(y), decoded_.ptr<std::uint16_t>(y),
                sizeof(std::uint16_t) * static_cast<std::size_t>(width));
  }
}

void ImageDecoder::readColor(const std::filesystem::path& root, const std::string& relative, int width, int height,
                             Image<Rgb8>& rgb) {
  readBytes(root, relative);
  // UNCHANGED rather than COLOR: a grey or 16-bit colour file is a different sensor setup and must
  // be reported, not silently converted.
  decode(bytes_, cv::IMREAD_UNCHANGED, relative, "truncated or not a PNG", width, height);
  const int channels = decoded_.channels();
  if (decoded_.depth() != CV_8U || (channels != 3 && channels != 4)) {
    throw Error(relative + ": colour must be an 8-bit 3- or 4-channel image, found " + describeType(decoded_.type()));
  }
  requireShape(relative, width, height);
  if (rgb.width() != width || rgb.height() != height) rgb.resize(width, height);
  for (int y = 0; y < height; ++y) {
    const std::uint8_t* in = decoded_.ptr<std::uint8_t>(y);
    Rgb8* out = rgb.view().row(y);
    for (int x = 0; x < width; ++x, in += channels) out[x] = {in[2], in[1], in[0]};  // OpenCV decodes to BGR(A)
  }
}

void ImageDecoder::decodeRgbOrder(std::span<const std::uint8_t> bytes, const std::string& what, int width, int height,
                                  Image<Rgb8>& rgb) {
  decode(bytes, cv::IMREAD_COLOR, what, "truncated or corrupt compressed image", width, height);
  requireShape(what, width, height);
  if (rgb.width() != width || rgb.height() != height) rgb.resize(width, height);
  for (int y = 0; y < height; ++y) {
    std::memcpy(rgb.view().row(y), decoded_.ptr<std::uint8_t>(y), 3 * static_cast<std::size_t>(width));
  }
}

}  // namespace vifusion::datasets::detail
