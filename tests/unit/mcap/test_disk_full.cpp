// Write errors stop the recording with a clear message and keep what was written readable: a real full
// filesystem (a 1 MiB tmpfs the test mounts; we run as root) and /dev/full.

#include <gtest/gtest.h>
#include <sys/mount.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "mcap_test_support.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"
#include "vifusion/mcap/recover_mcap.hpp"

namespace vifusion::mcap {
namespace {

using test::TestMessage;

constexpr std::int64_t kStartNs = 4'000 * kNsPerSecond;
constexpr std::uint16_t kChannels = 2;
constexpr const char* kTmpfsSize = "size=1m";
constexpr std::uint64_t kTmpfsBytes = 1024 * 1024;

/// A 1 MiB tmpfs mounted in a temporary directory for the test's lifetime.
class SmallFilesystem {
 public:
  SmallFilesystem() { mount_error_ = ::mount("tmpfs", dir_.path().c_str(), "tmpfs", 0, kTmpfsSize) == 0 ? 0 : errno; }
  ~SmallFilesystem() {
    if (mount_error_ == 0) ::umount2(dir_.path().c_str(), MNT_DETACH);
  }
  bool mounted() const { return mount_error_ == 0; }
  std::string whyNot() const {
    return "mount -t tmpfs -o " + std::string(kTmpfsSize) + " tmpfs " + dir_.path().string() +
           " failed: " + std::strerror(mount_error_) + " (the test needs root or CAP_SYS_ADMIN to make a full disk)";
  }
  std::string file(const std::string& name) const { return dir_.file(name); }

 private:
  test::TempDir dir_;
  int mount_error_ = 0;
};

TEST(McapDiskFull, TheWriterReportsEnospcAndTheBytesBeforeStayReadable) {
  SmallFilesystem filesystem;
  ASSERT_TRUE(filesystem.mounted()) << filesystem.whyNot();
  const std::string path = filesystem.file("full.mcap");
  McapWriterOptions options;  // fdatasync per chunk, as in the field
  options.chunk_target_bytes = 64 * 1024;
  McapWriter writer(options);
  ASSERT_TRUE(writer.open(path)) << writer.error();
  const std::uint16_t image = writer.registerChannel("/camera/depth", McapWriter::kNoId, "cdr");
  const std::uint16_t imu = writer.registerChannel("/imu", McapWriter::kNoId, "cdr");
  ASSERT_TRUE(writer.writeAttachment("calibration.yaml", "application/yaml", test::calibrationYaml(), kStartNs));

  // 10 kB images and 100-byte IMU samples until the disk is full: 2 MB would be twice its size.
  const std::vector<TestMessage> messages = test::makeMessages(400, kChannels, kStartNs, kNsPerMillisecond, 0, 0, 7);
  std::vector<TestMessage> sent;
  std::size_t accepted = 0;
  for (std::size_t i = 0; i < messages.size(); ++i) {
    TestMessage m = messages[i];
    m.channel_id = i % 2 == 0 ? image : imu;
    m.data.assign(i % 2 == 0 ? 10'000 : 100, static_cast<std::uint8_t>(i));
    if (!writer.write(m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns, m.data)) break;
    ++accepted;
    sent.push_back(m);
  }
  ASSERT_TRUE(writer.failed()) << "1 MiB took " << accepted << " messages without an error";
  EXPECT_LT(accepted, messages.size());
  EXPECT_NE(writer.error().find(path + ": write of "), std::string::npos) << writer.error();
  EXPECT_NE(writer.error().find("failed at byte offset "), std::string::npos) << writer.error();
  EXPECT_NE(writer.error().find("No space left on device"), std::string::npos) << writer.error();
  EXPECT_LE(writer.bytesWritten(), kTmpfsBytes);
  EXPECT_GT(writer.bytesWritten(), kTmpfsBytes * 3 / 4);
  const std::string first_error = writer.error();

  // Every later call is a no-op returning false, and the first message stays.
  EXPECT_TRUE(writer.reserveMessage(10).empty());
  EXPECT_FALSE(writer.write(imu, 0, kStartNs, kStartNs, sent[1].data));
  EXPECT_FALSE(writer.flushIfDue(kStartNs + kNsPerSecond));
  EXPECT_FALSE(writer.flush());
  EXPECT_EQ(writer.registerChannel("/late", McapWriter::kNoId, "cdr"), McapWriter::kNoId);
  EXPECT_FALSE(writer.writeAttachment("late.txt", "text/plain", {}, kStartNs));
  EXPECT_FALSE(writer.close());
  EXPECT_EQ(writer.error(), first_error);

  // What was written before is there: every message of every chunk written whole.
  McapReader reader(path);
  EXPECT_FALSE(reader.complete());
  ASSERT_GT(writer.messagesWritten(), 50u);
  const std::vector<TestMessage> read = test::readAll(reader);
  ASSERT_EQ(read.size(), writer.messagesWritten());
  EXPECT_TRUE(std::equal(read.begin(), read.end(), sent.begin()));
  EXPECT_EQ(reader.attachments().size(), 1u);

  // And recovery elsewhere gives a complete file with those messages.
  test::TempDir elsewhere;
  const RecoveryResult result = recoverMcap(path, elsewhere.file("recovered.mcap"));
  EXPECT_EQ(result.messages, writer.messagesWritten());
  McapReader recovered(elsewhere.file("recovered.mcap"));
  EXPECT_TRUE(recovered.summaryUsed()) << recovered.summaryProblem();
  EXPECT_EQ(test::readAll(recovered), read);
}

/// The descriptor this process holds open on `path` (from /proc/self/fd), or -1.
int descriptorOf(const std::string& path) {
  for (const auto& entry : std::filesystem::directory_iterator("/proc/self/fd")) {
    std::error_code error;
    if (std::filesystem::read_symlink(entry.path(), error) == path) return std::stoi(entry.path().filename());
  }
  return -1;
}

TEST(McapDiskFull, StorageGoneAwayIsReportedAndTheRecordingStopsCleanly) {
  // Closing the writer's descriptor behind its back stands in for unplugged storage: every later write
  // fails (EBADF here; EIO or ENODEV from a vanished USB disk take the same path).
  test::TempDir dir;
  const std::string path = dir.file("unplugged.mcap");
  McapWriterOptions options;
  options.chunk_target_bytes = 1024;
  McapWriter writer(options);
  ASSERT_TRUE(writer.open(path));
  const std::uint16_t imu = writer.registerChannel("/imu", McapWriter::kNoId, "cdr");
  const std::vector<std::uint8_t> sample(200, 0x11);
  for (std::uint32_t i = 0; i < 20; ++i) ASSERT_TRUE(writer.write(imu, i, kStartNs + i, kStartNs + i, sample));
  const std::uint64_t written_before = writer.bytesWritten();
  const std::uint64_t messages_before = writer.messagesWritten();
  const int fd = descriptorOf(path);
  ASSERT_GE(fd, 0) << "no descriptor open on " << path;
  ::close(fd);

  bool accepted = true;
  for (std::uint32_t i = 20; i < 40 && accepted; ++i)
    accepted = writer.write(imu, i, kStartNs + i, kStartNs + i, sample);
  EXPECT_FALSE(accepted);
  EXPECT_EQ(writer.error(), path + ": write of Chunk record failed at byte offset " + std::to_string(written_before) +
                                ": Bad file descriptor");
  EXPECT_FALSE(writer.close());

  McapReader reader(path);
  EXPECT_EQ(test::readAll(reader).size(), messages_before);
  EXPECT_EQ(messages_before, 20u);  // 4 chunks of 5 records of 31 + 200 bytes (1155 >= 1024)
}

TEST(McapDiskFull, OpeningOnAFullDeviceFailsWithTheReason) {
  McapWriter writer;
  EXPECT_FALSE(writer.open("/dev/full"));
  EXPECT_TRUE(writer.failed());
  EXPECT_EQ(writer.error(), "/dev/full: write of magic and Header failed at byte offset 0: No space left on device");
  EXPECT_FALSE(writer.close());

  McapWriter unwritable;
  EXPECT_FALSE(unwritable.open("/nonexistent-dir/run.mcap"));
  EXPECT_EQ(unwritable.error(),
            "/nonexistent-dir/run.mcap: cannot create the file at byte offset 0: No such file or directory");
}

}  // namespace
}  // namespace vifusion::mcap
