#pragma once
// Where McapReader reads from: a file (pread, so a multi-gigabyte recording is never loaded whole) or bytes
// in memory (tests, the fuzzer). The reader checks every offset against size() before reading.

#include <cstdint>
#include <span>
#include <string>

namespace vifusion::mcap {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  /// Total bytes, fixed when the source was opened.
  virtual std::uint64_t size() const = 0;
  /// Fills `out` from `offset`. @throws vifusion::Error on an I/O error or a range beyond size().
  virtual void read(std::uint64_t offset, std::span<std::uint8_t> out) const = 0;
  /// What messages call it: the file's path, or the name given to memory.
  virtual const std::string& name() const = 0;
};

class FileByteSource final : public ByteSource {
 public:
  /// @throws vifusion::Error naming the path when it cannot be opened or is not a regular file.
  explicit FileByteSource(const std::string& path);
  FileByteSource(const FileByteSource&) = delete;
  FileByteSource& operator=(const FileByteSource&) = delete;
  ~FileByteSource() override;

  std::uint64_t size() const override { return size_; }
  void read(std::uint64_t offset, std::span<std::uint8_t> out) const override;
  const std::string& name() const override { return path_; }

 private:
  int fd_ = -1;
  std::uint64_t size_ = 0;
  std::string path_;
};

/// Bytes owned by the caller, who keeps them alive while the source is used.
class MemoryByteSource final : public ByteSource {
 public:
  MemoryByteSource(std::span<const std::uint8_t> bytes, std::string name);

  std::uint64_t size() const override { return bytes_.size(); }
  void read(std::uint64_t offset, std::span<std::uint8_t> out) const override;
  const std::string& name() const override { return name_; }

 private:
  std::span<const std::uint8_t> bytes_;
  std::string name_;
};

}  // namespace vifusion::mcap
