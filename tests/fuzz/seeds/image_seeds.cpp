// Seeds of the image paths: small PNG and JPEG copies of a real 7-Scenes frame, and .klg logs whose frames
// are built from it (zlib depth, JPEG colour).

#include <zlib.h>

#include <cstdio>
#include <cstring>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <vector>

#include "seed_writer.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/test/klg_log.hpp"

namespace vifusion::fuzz::seeds {
namespace {

constexpr int kKlgWidth = 640, kKlgHeight = 480;  ///< the only size .klg logs have [px]

struct RealFrame {
  cv::Mat depth;  ///< 16UC1 [mm]
  cv::Mat bgr;    ///< 8UC3
};

RealFrame readRealFrame(const std::filesystem::path& data_dir) {
  const std::filesystem::path frames = data_dir / "7scenes-50/rgbd-frames";
  RealFrame frame{cv::imread((frames / "frame-000150.depth.png").string(), cv::IMREAD_UNCHANGED),
                  cv::imread((frames / "frame-000150.color.png").string(), cv::IMREAD_COLOR)};
  if (frame.depth.type() != CV_16UC1 || frame.bgr.type() != CV_8UC3) {
    throw Error(frames.string() + ": frame-000150's depth or colour PNG is missing or of the wrong type");
  }
  return frame;
}

std::vector<std::uint8_t> encoded(const char* extension, const cv::Mat& image, std::vector<int> params = {}) {
  std::vector<std::uint8_t> bytes;
  if (!cv::imencode(extension, image, bytes, params))
    throw Error(std::string("cannot encode a ") + extension + " seed");
  return bytes;
}

cv::Mat resized(const cv::Mat& image, int width, int height, int interpolation) {
  cv::Mat out;
  cv::resize(image, out, cv::Size(width, height), 0.0, 0.0, interpolation);
  return out;
}

std::vector<std::uint8_t> zlibCompressed(const cv::Mat& depth) {
  const auto raw_size = static_cast<uLong>(depth.total() * depth.elemSize());
  uLongf size = compressBound(raw_size);
  std::vector<std::uint8_t> out(size);
  if (compress2(out.data(), &size, depth.data, raw_size, Z_BEST_COMPRESSION) != Z_OK) throw Error("zlib failed");
  out.resize(size);
  return out;
}

}  // namespace

void writeImageSeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir) {
  enum : std::uint8_t { kDepthPng, kColorFile, kColorInMemory };  // fuzz_image_files.cpp's Path
  SeedWriter seeds(root, "fuzz_image_files");
  const RealFrame frame = readRealFrame(data_dir);
  for (const cv::Size size : {cv::Size(32, 24), cv::Size(16, 12)}) {
    char suffix[32];
    std::snprintf(suffix, sizeof(suffix), "_%dx%d", size.width, size.height);
    // The header bytes after the selector: width − 1 and height − 1 (the target adds 1).
    const std::vector<std::uint8_t> shape = {static_cast<std::uint8_t>(size.width - 1),
                                             static_cast<std::uint8_t>(size.height - 1)};
    const auto withShape = [&](std::vector<std::uint8_t> image) {
      image.insert(image.begin(), shape.begin(), shape.end());
      return image;
    };
    const cv::Mat depth = resized(frame.depth, size.width, size.height, cv::INTER_NEAREST);
    const cv::Mat bgr = resized(frame.bgr, size.width, size.height, cv::INTER_AREA);
    seeds.write(std::string("depth") + suffix + ".png", kDepthPng, withShape(encoded(".png", depth)));
    seeds.write(std::string("color") + suffix + ".png", kColorFile, withShape(encoded(".png", bgr)));
    seeds.write(std::string("color") + suffix + ".jpg", kColorFile,
                withShape(encoded(".jpg", bgr, {cv::IMWRITE_JPEG_QUALITY, 80})));
    seeds.write(std::string("memory") + suffix + ".jpg", kColorInMemory,
                withShape(encoded(".jpg", bgr, {cv::IMWRITE_JPEG_QUALITY, 80})));
  }
}

void writeKlgSeeds(const std::filesystem::path& root, const std::filesystem::path& data_dir) {
  SeedWriter seeds(root, "fuzz_klg_reader");
  const RealFrame frame = readRealFrame(data_dir);
  // Coarse depth (20×15 blocks of the real frame) compresses to a few hundred bytes, and a low-quality JPEG to
  // a few kB, so a whole two-frame log stays small enough to fuzz quickly.
  const cv::Mat blocky_depth =
      resized(resized(frame.depth, 20, 15, cv::INTER_NEAREST), kKlgWidth, kKlgHeight, cv::INTER_NEAREST);
  const cv::Mat blocky_bgr =
      resized(resized(frame.bgr, 40, 30, cv::INTER_AREA), kKlgWidth, kKlgHeight, cv::INTER_NEAREST);
  const std::vector<std::uint8_t> depth = zlibCompressed(blocky_depth);
  const std::vector<std::uint8_t> jpeg = encoded(".jpg", blocky_bgr, {cv::IMWRITE_JPEG_QUALITY, 10});
  seeds.write("jpeg_and_empty.klg", std::nullopt,
              test::klgBytes({{5'000'000, depth, jpeg}, {5'033'333, depth, {}}}, 2));
  seeds.write("one_frame.klg", std::nullopt, test::klgBytes({{0, depth, jpeg}}, 1));
}

}  // namespace vifusion::fuzz::seeds
