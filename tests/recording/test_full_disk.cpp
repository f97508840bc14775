// Issue 18 acceptance, full disk: `vifusion record` of the 2 s dataset (23 MB of images) into an 8 MiB tmpfs
// that the test mounts (we run as root). The recording must end with exit code 6 and a message naming the file
// and the cause, and what was written before must read back as a bit-exact prefix of the dataset.

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <string>

#include "recording_test_support.hpp"
#include "vifusion/config/daemon_config.hpp"
#include "vifusion/recording/recording_reader.hpp"

namespace vifusion::test {
namespace {

constexpr const char* kTmpfsOptions = "size=8m";
constexpr std::uintmax_t kTmpfsBytes = 8u << 20;

/// An 8 MiB tmpfs on a fresh directory under /tmp for the test's lifetime.
class SmallFilesystem {
 public:
  SmallFilesystem() {
    char pattern[] = "/tmp/vifusion_full_disk_XXXXXX";
    if (::mkdtemp(pattern) == nullptr) {
      mount_error_ = errno;
      return;
    }
    dir_ = pattern;
    mount_error_ = ::mount("tmpfs", dir_.c_str(), "tmpfs", 0, kTmpfsOptions) == 0 ? 0 : errno;
  }
  ~SmallFilesystem() {
    if (mount_error_ == 0) ::umount2(dir_.c_str(), MNT_DETACH);
    if (!dir_.empty()) ::rmdir(dir_.c_str());
  }
  SmallFilesystem(const SmallFilesystem&) = delete;
  SmallFilesystem& operator=(const SmallFilesystem&) = delete;

  bool mounted() const { return mount_error_ == 0; }
  std::string whyNot() const {
    return "mount -t tmpfs -o " + std::string(kTmpfsOptions) + " tmpfs " + dir_.string() +
           " failed: " + std::strerror(mount_error_) + " (the test needs root or CAP_SYS_ADMIN to make a full disk)";
  }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
  int mount_error_ = 0;
};

TEST(RecordingFullDisk, EndsWithExitCode6AMessageAndTheFramesBeforeIntact) {
  ASSERT_GE(datasetContents().frames.size(), 2u) << kDatasetDir;
  SmallFilesystem filesystem;
  ASSERT_TRUE(filesystem.mounted()) << filesystem.whyNot();
  const std::filesystem::path path = filesystem.dir() / "x.mcap";
  std::filesystem::create_directories(kWorkDir);

  std::string out, err;
  const int code =
      runToEnd({kVifusionCli, "record", "--source", "dataset:" + kDatasetDir.string(), "--out", path.string()},
               kWorkDir / "full_disk", &out, &err);
  std::printf("vifusion record into %s (exit code %d):\n  stdout: %s  stderr: %s", path.c_str(), code, out.c_str(),
              err.c_str());
  EXPECT_EQ(code, config::kExitOutput);
  EXPECT_NE(err.find(path.string()), std::string::npos) << err;
  EXPECT_NE(err.find("No space left on device"), std::string::npos) << err;
  const std::uintmax_t file_bytes = std::filesystem::file_size(path);
  EXPECT_LE(file_bytes, kTmpfsBytes);

  recording::RecordingReader reader(path);
  std::printf("  %ju bytes on disk; RecordingReader: %zu frames; note: %s\n", file_bytes, reader.frameCount(),
              reader.note().c_str());
  EXPECT_FALSE(reader.note().empty()) << "a recording ended by a full disk has no summary";
  const PrefixCounts prefix = expectDatasetPrefix(reader);
  EXPECT_GE(prefix.frames, 1u);
  EXPECT_LT(prefix.frames, datasetContents().frames.size());
  std::printf("  a bit-exact prefix of the dataset: %zu of %zu frames, %zu IMU samples\n", prefix.frames,
              datasetContents().frames.size(), prefix.imu_samples);
}

}  // namespace
}  // namespace vifusion::test
