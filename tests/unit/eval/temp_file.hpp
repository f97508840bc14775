#pragma once
// A file in the system temp directory with a unique name, removed when the test ends.

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace vifusion::eval::test {

class TempFile {
 public:
  TempFile(const std::string& name, const std::string& contents)
      : path_(std::filesystem::temp_directory_path() /
              ("vifusion_" + std::to_string(::getpid()) + "_" + std::to_string(counter_++) + "_" + name)) {
    std::ofstream(path_, std::ios::binary) << contents;
  }
  ~TempFile() { std::filesystem::remove(path_); }
  TempFile(const TempFile&) = delete;
  TempFile& operator=(const TempFile&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  static inline int counter_ = 0;
  std::filesystem::path path_;
};

}  // namespace vifusion::eval::test
