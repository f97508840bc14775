#pragma once
// Fixture helpers for the dataset reader tests: a temporary folder removed afterwards, small files
// written from strings, images written with OpenCV, and a check on boundary-error wording.

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <string>
#include <vector>

#include "vifusion/test/expect_error.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::datasets::test {

/// A fresh folder under the system temp dir, named after the running test; removed on destruction.
class TempDir {
 public:
  TempDir() {
    static std::atomic<int> counter{0};
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    const std::string name = std::string("vifusion_datasets_") + (info ? info->name() : "test") + "_" +
                             std::to_string(::getpid()) + "_" + std::to_string(counter++);
    path_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& relative) const { return path_ / relative; }

 private:
  std::filesystem::path path_;
};

inline void writeText(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << text;
}

inline void writeBytes(const std::filesystem::path& path, const std::vector<std::uint8_t>& bytes) {
  std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary).write(reinterpret_cast<const char*>(bytes.data()),
                                             static_cast<std::streamsize>(bytes.size()));
}

/// Depth value at (x, y) of the synthetic depth fixtures: distinct per pixel and frame.
inline std::uint16_t depthPattern(int x, int y, int frame) {
  return static_cast<std::uint16_t>(1000 + 7 * x + 13 * y + 101 * frame);
}

/// Colour (R, G, B) at (x, y) of the synthetic colour fixtures.
inline cv::Vec3b rgbPattern(int x, int y, int frame) {
  return {static_cast<std::uint8_t>(x + frame), static_cast<std::uint8_t>(y), static_cast<std::uint8_t>(200 - frame)};
}

inline cv::Mat depthImage(int width, int height, int frame) {
  cv::Mat depth(height, width, CV_16UC1);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) depth.at<std::uint16_t>(y, x) = depthPattern(x, y, frame);
  }
  return depth;
}

/// BGR as OpenCV writes it, holding rgbPattern.
inline cv::Mat colorImageBgr(int width, int height, int frame) {
  cv::Mat bgr(height, width, CV_8UC3);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const cv::Vec3b rgb = rgbPattern(x, y, frame);
      bgr.at<cv::Vec3b>(y, x) = {rgb[2], rgb[1], rgb[0]};
    }
  }
  return bgr;
}

inline void writePng(const std::filesystem::path& path, const cv::Mat& image) {
  std::filesystem::create_directories(path.parent_path());
  ASSERT_TRUE(cv::imwrite(path.string(), image)) << path;
}

/// A TUM-layout sequence: rgb/<stamp>.png and depth/<stamp>.png for each stamp (decimal seconds, as
/// written in the index), rgb.txt and depth.txt. Frame k holds rgbPattern/depthPattern(·, ·, k).
inline void writeTumFrames(const std::filesystem::path& dir, const std::vector<std::string>& rgb_stamps,
                           const std::vector<std::string>& depth_stamps, int width = 640, int height = 480) {
  std::string rgb_index = "# color images\n# timestamp filename\n";
  std::string depth_index = "# depth maps\n# timestamp filename\n";
  for (std::size_t k = 0; k < rgb_stamps.size(); ++k) {
    writePng(dir / "rgb" / (rgb_stamps[k] + ".png"), colorImageBgr(width, height, static_cast<int>(k)));
    rgb_index += rgb_stamps[k] + " rgb/" + rgb_stamps[k] + ".png\n";
  }
  for (std::size_t k = 0; k < depth_stamps.size(); ++k) {
    writePng(dir / "depth" / (depth_stamps[k] + ".png"), depthImage(width, height, static_cast<int>(k)));
    depth_index += depth_stamps[k] + " depth/" + depth_stamps[k] + ".png\n";
  }
  writeText(dir / "rgb.txt", rgb_index);
  writeText(dir / "depth.txt", depth_index);
}

/// True when `frame` holds pattern frame `k` at every pixel.
template <typename Frame>
::testing::AssertionResult holdsPattern(const Frame& frame, int k) {
  for (int y = 0; y < frame.depth.height(); ++y) {
    for (int x = 0; x < frame.depth.width(); ++x) {
      if (frame.depth(x, y) != depthPattern(x, y, k)) {
        return ::testing::AssertionFailure() << "depth(" << x << ", " << y << ") = " << frame.depth(x, y);
      }
      const cv::Vec3b rgb = rgbPattern(x, y, k);
      const auto& pixel = frame.rgb(x, y);
      if (pixel.r != rgb[0] || pixel.g != rgb[1] || pixel.b != rgb[2]) {
        return ::testing::AssertionFailure() << "rgb(" << x << ", " << y << ") differs";
      }
    }
  }
  return ::testing::AssertionSuccess();
}

/// Keeps only the first half of a file, as an interrupted copy would.
inline void truncateFile(const std::filesystem::path& path) {
  std::filesystem::resize_file(path, std::filesystem::file_size(path) / 2);
}

using vifusion::test::expectError;

}  // namespace vifusion::datasets::test
