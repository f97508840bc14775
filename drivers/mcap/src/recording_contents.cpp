#include "recording_contents.hpp"

#include "record_parser.hpp"

namespace vifusion::mcap::detail {
namespace {

constexpr std::int32_t kNoSlot = -1;

std::int32_t slotOf(const std::vector<std::int32_t>& slots, std::uint16_t id) {
  return id < slots.size() ? slots[id] : kNoSlot;
}

void setSlot(std::vector<std::int32_t>& slots, std::uint16_t id, std::size_t index) {
  if (id >= slots.size()) slots.resize(static_cast<std::size_t>(id) + 1, kNoSlot);
  slots[id] = static_cast<std::int32_t>(index);
}

}  // namespace

bool RecordingContents::addSchema(SchemaInfo&& schema, std::string& problem) {
  if (schema.id == 0) return true;
  if (const SchemaInfo* existing = this->schema(schema.id)) {
    if (sameSchema(*existing, schema)) return true;
    problem = "Schema " + std::to_string(schema.id) + " (\"" + schema.name + "\") differs from its earlier definition";
    return false;
  }
  setSlot(schema_slot_, schema.id, schemas.size());
  schemas.push_back(std::move(schema));
  return true;
}

bool RecordingContents::addChannel(ChannelInfo&& channel, std::string& problem) {
  if (channel.schema_id != 0 && schema(channel.schema_id) == nullptr) {
    problem = "Channel " + std::to_string(channel.id) + " (\"" + channel.topic + "\") refers to schema " +
              std::to_string(channel.schema_id) + ", which is not defined before it";
    return false;
  }
  if (const ChannelInfo* existing = this->channel(channel.id)) {
    if (sameChannel(*existing, channel)) return true;
    problem =
        "Channel " + std::to_string(channel.id) + " (\"" + channel.topic + "\") differs from its earlier definition";
    return false;
  }
  setSlot(channel_slot_, channel.id, channels.size());
  channels.push_back(std::move(channel));
  return true;
}

const SchemaInfo* RecordingContents::schema(std::uint16_t id) const {
  const std::int32_t slot = slotOf(schema_slot_, id);
  return slot == kNoSlot ? nullptr : &schemas[static_cast<std::size_t>(slot)];
}

const ChannelInfo* RecordingContents::channel(std::uint16_t id) const {
  const std::int32_t slot = slotOf(channel_slot_, id);
  return slot == kNoSlot ? nullptr : &channels[static_cast<std::size_t>(slot)];
}

void RecordingContents::truncateDefinitions(std::size_t schema_count, std::size_t channel_count) {
  for (std::size_t i = schema_count; i < schemas.size(); ++i) schema_slot_[schemas[i].id] = kNoSlot;
  for (std::size_t i = channel_count; i < channels.size(); ++i) channel_slot_[channels[i].id] = kNoSlot;
  schemas.resize(schema_count);
  channels.resize(channel_count);
}

void RecordingContents::clearFound() {
  truncateDefinitions(0, 0);
  attachments.clear();
  statistics = {};
  chunks.clear();
  items.clear();
}

}  // namespace vifusion::mcap::detail
