// libFuzzer target: McapReader (drivers/mcap) on arbitrary files. Two kinds of input, chosen by the first
// byte's low bit:
//  - raw: the rest of the input is the file;
//  - edited: a small valid recording (written once by McapWriter: two channels, an attachment, several
//    chunks, a summary) is cut at the length bytes 1..2 choose and then XOR-edited at the (offset u16,
//    mask u8) triples that follow, which reaches the deep paths (chunk CRCs, summary CRC, record fields)
//    that random bytes rarely do.
// Besides "no crash, no sanitizer report, only vifusion::Error" it checks what the reader promises:
//  - every message names a channel the reader defines;
//  - a scanned file (no usable summary) gives exactly the messages its statistics count, since the scan
//    checked every accepted chunk whole;
//  - an unedited cut of the valid recording opens and gives a prefix of its messages.

#include <stdlib.h>
#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "vifusion/core/error.hpp"
#include "vifusion/mcap/byte_source.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"

namespace {

using namespace vifusion::mcap;

constexpr std::size_t kMagicBytes = 8;
constexpr std::size_t kEditBytes = 3;             // offset u16 little-endian, XOR mask u8
constexpr std::size_t kEditedHeaderBytes = 3;     // mode byte, cut length u16
constexpr std::int64_t kStartNs = 1'000'000'000;  // log times of the base recording
constexpr int kMaxReadsAfterErrors = 10'000;      // bound on readNext() calls, errors included

void require(bool condition) {
  if (!condition) __builtin_trap();
}

/// The base recording, written once: 24 messages on two channels in ~200-byte chunks.
const std::vector<std::uint8_t>& baseRecording() {
  static const std::vector<std::uint8_t> bytes = [] {
    char path[] = "/tmp/fuzz_mcap_reader-XXXXXX";
    const int fd = ::mkstemp(path);
    require(fd >= 0);
    ::close(fd);
    McapWriterOptions options;
    options.sync = SyncPolicy::kNone;
    options.chunk_target_bytes = 200;
    {
      McapWriter writer(options);
      require(writer.open(path));
      const std::uint8_t text[] = {'i', 'n', 't', '8', ' ', 'x'};
      const std::uint16_t schema = writer.registerSchema("pkg/msg/X", "ros2msg", text);
      const std::uint16_t a = writer.registerChannel("/a", schema, "cdr", {{"k", "v"}});
      const std::uint16_t b = writer.registerChannel("/b", 0, "cdr");
      for (std::uint32_t i = 0; i < 24; ++i) {
        if (i == 12) require(writer.writeAttachment("calibration.yaml", "application/yaml", text, kStartNs));
        std::uint8_t data[20];
        for (std::uint8_t& byte : data) byte = static_cast<std::uint8_t>(i * 13);
        require(writer.write(i % 2 == 0 ? a : b, i, kStartNs + i, kStartNs + i, std::span(data, 1 + i % 20)));
      }
      require(writer.close());
    }
    std::ifstream in(path, std::ios::binary);
    std::vector<std::uint8_t> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    ::unlink(path);
    return file;
  }();
  return bytes;
}

/// Opens and reads `file` whole; returns the messages read (or -1 when it is refused).
long readWhole(std::span<const std::uint8_t> file) {
  try {
    McapReader reader(std::make_unique<MemoryByteSource>(file, "fuzz.mcap"));
    long messages = 0;
    bool any_error = false;
    MessageView view;
    for (int call = 0; call < kMaxReadsAfterErrors; ++call) {
      try {
        if (!reader.readNext(view)) break;
        require(reader.channel(view.channel_id) != nullptr);
        require(view.data.data() != nullptr || view.data.empty());
        ++messages;
      } catch (const vifusion::Error&) {
        any_error = true;  // a corrupt chunk behind an intact summary: read on
      }
    }
    if (!reader.summaryUsed()) {
      require(!any_error);
      require(static_cast<std::uint64_t>(messages) == reader.statistics().message_count);
      require(reader.chunks().size() == reader.statistics().chunk_count);
    }
    return messages;
  } catch (const vifusion::Error&) {
    return -1;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  if ((data[0] & 1u) == 0) {
    readWhole({data + 1, size - 1});
    return 0;
  }
  if (size < kEditedHeaderBytes) return 0;
  const std::vector<std::uint8_t>& base = baseRecording();
  const std::size_t cut =
      (static_cast<std::size_t>(data[1]) | static_cast<std::size_t>(data[2]) << 8) % (base.size() + 1);
  std::vector<std::uint8_t> file(base.begin(), base.begin() + static_cast<std::ptrdiff_t>(cut));
  bool edited = false;
  for (std::size_t at = kEditedHeaderBytes; at + kEditBytes <= size; at += kEditBytes) {
    if (file.empty()) break;
    const std::size_t offset =
        (static_cast<std::size_t>(data[at]) | static_cast<std::size_t>(data[at + 1]) << 8) % file.size();
    file[offset] ^= data[at + 2];
    edited = edited || data[at + 2] != 0;
  }
  const long messages = readWhole(file);
  if (!edited && cut >= kMagicBytes) require(messages >= 0);  // a cut valid file always opens
  return 0;
}
