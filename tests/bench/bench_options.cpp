#include "bench_options.hpp"

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "vifusion/core/error.hpp"

namespace vifusion::bench {
namespace {

std::vector<Size> parseSizes(const std::string& text) {
  std::vector<Size> sizes;
  std::size_t begin = 0;
  while (begin <= text.size()) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    const std::string item = text.substr(begin, end - begin);
    Size size;
    char x = 0;
    char rest = 0;
    if (std::sscanf(item.c_str(), "%d%c%d%c", &size.width, &x, &size.height, &rest) != 3 || x != 'x' ||
        size.width < 16 || size.height < 16 || size.width % 2 != 0) {
      throw Error("--sizes: '" + item + "' is not WIDTHxHEIGHT (even width, both ≥ 16)");
    }
    sizes.push_back(size);
    begin = end + 1;
  }
  return sizes;
}

}  // namespace

bool takeFlag(const char* arg, const char* name, std::string& value) {
  const std::size_t n = std::strlen(name);
  if (std::strncmp(arg, name, n) != 0 || arg[n] != '=') return false;
  value = arg + n + 1;
  return true;
}

bool parseBoolFlag(const std::string& flag, const std::string& value) {
  if (value == "1" || value == "true") return true;
  if (value == "0" || value == "false") return false;
  throw Error(flag + ": expected 1 or 0, got '" + value + "'");
}

int parseIntFlag(const std::string& flag, const std::string& value, int min, int max) {
  char* end = nullptr;
  const long parsed = std::strtol(value.c_str(), &end, 10);
  if (value.empty() || *end != '\0' || parsed < min || parsed > max) {
    throw Error(flag + ": expected an integer in [" + std::to_string(min) + ", " + std::to_string(max) + "], got '" +
                value + "'");
  }
  return static_cast<int>(parsed);
}

BenchOptions& options() {
  static BenchOptions instance;
  return instance;
}

gpu::GpuContext& context() {
  static const auto instance = gpu::GpuContext::create(gpu::GpuOptions{}.withEnvironment());
  return *instance;
}

void parseOptions(int& argc, char** argv) {
  BenchOptions& o = options();
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    std::string value;
    if (takeFlag(argv[i], "--frames", value)) {
      char* end = nullptr;
      const long frames = std::strtol(value.c_str(), &end, 10);
      if (*end != '\0' || frames < 4 || frames > 100000)
        throw Error("--frames: expected 4 … 100000, got '" + value + "'");
      o.frames = static_cast<int>(frames);
    } else if (takeFlag(argv[i], "--sizes", value)) {
      o.sizes = parseSizes(value);
    } else if (takeFlag(argv[i], "--data_dir", value)) {
      o.data_dir = value;
    } else if (takeFlag(argv[i], "--vifusion", value)) {
      o.vifusion = value;
    } else if (takeFlag(argv[i], "--noise", value)) {
      o.noise = parseBoolFlag("--noise", value);
    } else if (takeFlag(argv[i], "--photometric", value)) {
      o.photometric = parseBoolFlag("--photometric", value);
    } else if (takeFlag(argv[i], "--opencv", value)) {
      o.opencv = parseBoolFlag("--opencv", value);
    } else if (takeFlag(argv[i], "--open3d", value)) {
      o.open3d = parseBoolFlag("--open3d", value);
    } else if (takeFlag(argv[i], "--mode", value)) {
      // gyro mode is `vifusion run`'s experiment, not a configuration this benchmark measures.
      if (value != "rgbd" && value != "rgbdi") throw Error("--mode: expected rgbd or rgbdi, got '" + value + "'");
      o.mode = value;
    } else if (takeFlag(argv[i], "--trajectory_dir", value)) {
      o.trajectory_dir = value;
    } else if (takeFlag(argv[i], "--steps", value)) {
      o.steps = parseBoolFlag("--steps", value);
    } else {
      if (std::strcmp(argv[i], "--help") == 0) {
        std::printf(
            "bench_rgbd_slam [--frames=%d] [--sizes=640x480,320x240] [--data_dir=%s]\n"
            "                [--vifusion=%s] [--noise=1] [--photometric=1] [--opencv=1]\n"
            "                [--open3d=1] [--mode=rgbd|rgbdi] [--steps=1] [--trajectory_dir=DIR]\n"
            "                [Google Benchmark flags]\n\n",
            o.frames, o.data_dir.c_str(), o.vifusion.c_str());
      }
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
}

}  // namespace vifusion::bench
