#pragma once
// A typed DDS writer on one of vifusion's topics (topics.hpp), owning its topic and writer entities.

#include <cstdint>
#include <string>

#include "vifusion/dds/entity.hpp"
#include "vifusion/dds/participant.hpp"
#include "vifusion/dds/topics.hpp"

namespace vifusion::dds {
namespace detail {

/// The type-independent part of Writer<Msg>.
class WriterBase {
 public:
  WriterBase(const Participant& participant, const dds_topic_descriptor_t& descriptor, std::string_view name,
             const TopicQos& qos);

  /// Serialises and sends `sample`. Returns false when the sample was dropped because a reliable
  /// reader kept the history full for longer than the blocking limit; throws vifusion::Error on
  /// anything else (a deleted participant, an invalid sample).
  bool write(const void* sample);
  /// Readers currently matched, remote and local.
  std::uint32_t matchedReaders() const;
  dds_entity_t topic() const { return topic_.get(); }
  dds_entity_t writer() const { return writer_.get(); }

 private:
  std::string name_;
  Entity topic_;  // deleted after the writer that uses it
  Entity writer_;
};

}  // namespace detail

template <typename Msg>
class Writer {
 public:
  Writer(const Participant& participant, const Topic<Msg>& topic)
      : base_(participant, msg::Descriptor<Msg>::get(), topic.name, topic.qos) {}

  /// See detail::WriterBase::write. Allocates nothing of ours: Cyclone serialises `message` (and the
  /// strings and buffers it borrows) into its own buffer before returning.
  bool write(const Msg& message) { return base_.write(&message); }
  std::uint32_t matchedReaders() const { return base_.matchedReaders(); }
  dds_entity_t topic() const { return base_.topic(); }
  dds_entity_t writer() const { return base_.writer(); }

 private:
  detail::WriterBase base_;
};

}  // namespace vifusion::dds
