// mcap_node_fixture DIR: writes recordings for the independent reader test (tests/node/read_mcap.mjs, on
// Foxglove's @mcap/core) and what that reader must find in them, as JSON lines:
//   complete.mcap          closed normally: three channels on two schemas, 300 messages in ~2 kB chunks,
//                          the calibration attachment after half of them;
//   cut.mcap               its first bytes up to the middle of its middle chunk, as a kill leaves it;
//   complete.indexed.jsonl McapIndexedReader on complete.mcap: every message, statistics, attachment;
//   complete.stream.jsonl  McapStreamReader on complete.mcap: every message, done;
//   cut.stream.jsonl       McapStreamReader on cut.mcap: the messages of the chunks before the cut, not
//                          done, and the partial chunk's bytes left over.
// The expectations come from what this program wrote (messages, ids, chunk boundaries from the writer's
// counters), not from reading the files back, except for the chunk offsets that choose the cut.

#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "vifusion/core/crc32.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/mcap/mcap_reader.hpp"
#include "vifusion/mcap/mcap_writer.hpp"

namespace {

using namespace vifusion::mcap;

constexpr std::size_t kMessages = 300;
constexpr std::uint16_t kChannels = 3;
constexpr std::int64_t kStartNs = 1'700'000'000'000'000'000;  // a Unix-epoch time, as ROS 2 bags use
constexpr std::int64_t kPeriodNs = 1'000'000;
constexpr std::int64_t kPublishLeadNs = 250'000;
constexpr std::size_t kMaxDataBytes = 200;
constexpr std::size_t kHeadBytes = 8;
constexpr std::size_t kChunkTargetBytes = 2048;
constexpr std::int64_t kAttachmentLogTimeNs = kStartNs + 150 * kPeriodNs;

struct Written {
  std::uint16_t channel_id = 0;
  std::uint32_t sequence = 0;
  std::int64_t log_time_ns = 0;
  std::int64_t publish_time_ns = 0;
  std::vector<std::uint8_t> data;
};

const char* const kTopics[kChannels] = {"/camera/imu", "/camera/depth/image_rect_raw", "/camera/color/image_raw"};
const char* const kSchemaNames[2] = {"sensor_msgs/msg/Imu", "sensor_msgs/msg/Image"};

std::vector<std::uint8_t> bytesOf(const std::string& text) { return {text.begin(), text.end()}; }

std::string hex(const std::vector<std::uint8_t>& data) {
  std::string out;
  char digits[3];
  for (std::size_t i = 0; i < data.size() && i < kHeadBytes; ++i) {
    std::snprintf(digits, sizeof(digits), "%02x", data[i]);
    out += digits;
  }
  return out;
}

std::string messageLine(const Written& m) {
  const std::uint16_t schema = m.channel_id == 1 ? 0 : 1;
  return "{\"topic\":\"" + std::string(kTopics[m.channel_id - 1]) + "\",\"schema\":\"" + kSchemaNames[schema] +
         "\",\"schema_encoding\":\"ros2msg\",\"message_encoding\":\"cdr\",\"channel_id\":" +
         std::to_string(m.channel_id) + ",\"sequence\":" + std::to_string(m.sequence) + ",\"log_time\":\"" +
         std::to_string(m.log_time_ns) + "\",\"publish_time\":\"" + std::to_string(m.publish_time_ns) +
         "\",\"size\":" + std::to_string(m.data.size()) + ",\"head\":\"" + hex(m.data) +
         "\",\"crc32\":" + std::to_string(vifusion::crc32(m.data)) + "}\n";
}

std::string attachmentsJson(const std::vector<std::uint8_t>& yaml) {
  return "[{\"name\":\"calibration.yaml\",\"media_type\":\"application/yaml\",\"log_time\":\"" +
         std::to_string(kAttachmentLogTimeNs) + "\",\"size\":" + std::to_string(yaml.size()) +
         ",\"crc32\":" + std::to_string(vifusion::crc32(yaml)) + "}]";
}

void writeText(const std::filesystem::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out) throw vifusion::Error(path.string() + ": cannot write");
}

int run(const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  const std::vector<std::uint8_t> yaml = bytesOf("cam0:\n  intrinsics: [615.0, 615.0, 320.0, 240.0]\n");

  McapWriterOptions options;
  options.chunk_target_bytes = kChunkTargetBytes;
  McapWriter writer(options);
  const std::string complete_path = (dir / "complete.mcap").string();
  if (!writer.open(complete_path)) throw vifusion::Error(writer.error());
  const std::uint16_t imu = writer.registerSchema(kSchemaNames[0], "ros2msg", bytesOf("float64 x\n"));
  const std::uint16_t image = writer.registerSchema(kSchemaNames[1], "ros2msg", bytesOf("uint32 height\n"));
  for (std::uint16_t c = 0; c < kChannels; ++c) {
    writer.registerChannel(kTopics[c], c == 0 ? imu : image, "cdr", {{"offered_qos_profiles", ""}});
  }
  std::vector<Written> messages;
  std::vector<std::uint64_t> messages_through_chunk;
  std::uint64_t attachment_end = 0;  // it goes into the file at once, before the chunk being filled
  for (std::size_t i = 0; i < kMessages; ++i) {
    if (i == kMessages / 2) {
      writer.writeAttachment("calibration.yaml", "application/yaml", yaml, kAttachmentLogTimeNs);
      attachment_end = writer.bytesWritten();
    }
    Written m;
    m.channel_id = static_cast<std::uint16_t>(1 + i % kChannels);
    m.sequence = static_cast<std::uint32_t>(i / kChannels);
    m.log_time_ns = kStartNs + static_cast<std::int64_t>(i) * kPeriodNs;
    m.publish_time_ns = m.log_time_ns - kPublishLeadNs;
    m.data.resize((i * 37) % (kMaxDataBytes + 1));
    for (std::size_t b = 0; b < m.data.size(); ++b) m.data[b] = static_cast<std::uint8_t>(i * 31 + b * 7);
    if (!writer.write(m.channel_id, m.sequence, m.log_time_ns, m.publish_time_ns, m.data)) {
      throw vifusion::Error(writer.failed() ? writer.error() : writer.firstRejection());
    }
    while (messages_through_chunk.size() < writer.chunksWritten()) {
      messages_through_chunk.push_back(writer.messagesWritten());
    }
    messages.push_back(std::move(m));
  }
  if (!writer.close()) throw vifusion::Error(writer.error());
  while (messages_through_chunk.size() < writer.chunksWritten()) {
    messages_through_chunk.push_back(writer.messagesWritten());
  }

  std::string all_lines;
  std::map<std::uint16_t, std::uint64_t> per_channel;
  for (const Written& m : messages) {
    all_lines += messageLine(m);
    ++per_channel[m.channel_id];
  }
  std::string counts;
  for (const auto& [channel, count] : per_channel) {
    counts += (counts.empty() ? "\"" : ",\"") + std::to_string(channel) + "\":\"" + std::to_string(count) + "\"";
  }
  const std::string chunks = std::to_string(writer.chunksWritten());
  const std::string common = "\"profile\":\"ros2\",\"library\":\"vifusion\",\"schemas\":2,\"channels\":3,";
  writeText(dir / "complete.indexed.jsonl",
            all_lines + "{\"summary\":{\"reader\":\"indexed\"," + common + "\"messages\":" + std::to_string(kMessages) +
                ",\"chunks\":" + chunks + ",\"attachments\":" + attachmentsJson(yaml) +
                ",\"statistics\":{\"message_count\":\"" + std::to_string(kMessages) + "\",\"chunk_count\":" + chunks +
                ",\"attachment_count\":1,\"message_start_time\":\"" + std::to_string(messages.front().log_time_ns) +
                "\",\"message_end_time\":\"" + std::to_string(messages.back().log_time_ns) +
                "\",\"channel_message_counts\":{" + counts + "}}}}\n");
  writeText(dir / "complete.stream.jsonl", all_lines + "{\"summary\":{\"reader\":\"stream\"," + common +
                                               "\"messages\":" + std::to_string(kMessages) + ",\"chunks\":" + chunks +
                                               ",\"attachments\":" + attachmentsJson(yaml) +
                                               ",\"done\":true,\"trailing_bytes\":0}}\n");

  // Cut in the middle of the middle chunk: the chunks before it (and their indexes) are whole.
  const std::vector<ChunkInfo> chunk_infos = McapReader(complete_path).chunks();
  const std::size_t cut_chunk = chunk_infos.size() / 2;
  const ChunkInfo& cut_info = chunk_infos[cut_chunk];
  const std::uint64_t cut = cut_info.offset + cut_info.record_bytes / 2;
  std::ifstream in(complete_path, std::ios::binary);
  std::vector<char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  bytes.resize(static_cast<std::size_t>(cut));
  std::ofstream(dir / "cut.mcap", std::ios::binary).write(bytes.data(), static_cast<std::streamsize>(bytes.size()));

  const std::uint64_t kept = messages_through_chunk[cut_chunk - 1];
  std::string cut_lines;
  for (std::size_t i = 0; i < kept; ++i) cut_lines += messageLine(messages[i]);
  const bool attachment_kept = attachment_end <= cut;
  writeText(dir / "cut.stream.jsonl",
            cut_lines + "{\"summary\":{\"reader\":\"stream\"," + common + "\"messages\":" + std::to_string(kept) +
                ",\"chunks\":" + std::to_string(cut_chunk) +
                ",\"attachments\":" + (attachment_kept ? attachmentsJson(yaml) : "[]") +
                ",\"done\":false,\"trailing_bytes\":" + std::to_string(cut - cut_info.offset) + "}}\n");
  std::printf(
      "mcap_node_fixture: %zu messages in %s chunks; cut.mcap cut at byte %llu inside chunk %zu, keeping %llu\n",
      kMessages, chunks.c_str(), static_cast<unsigned long long>(cut), cut_chunk,
      static_cast<unsigned long long>(kept));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: mcap_node_fixture DIR\n");
    return 2;
  }
  try {
    return run(argv[1]);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "mcap_node_fixture: %s\n", e.what());
    return 1;
  }
}
