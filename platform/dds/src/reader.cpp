#include "vifusion/dds/reader.hpp"

#include "qos.hpp"

namespace vifusion::dds::detail {

ReaderBase::ReaderBase(const Participant& participant, const dds_topic_descriptor_t& descriptor, std::string_view name,
                       const TopicQos& qos)
    : name_(name) {
  const std::string what = "DDS reader on '" + name_ + "'";
  topic_ = Entity(checkEntity(dds_create_topic(participant.participant(), &descriptor, name_.c_str(), nullptr, nullptr),
                              what + ": creating the topic"));
  const QosPtr reader_qos = endpointQos(qos, Endpoint::Reader);
  reader_ =
      Entity(checkEntity(dds_create_reader(participant.subscriber(), topic_.get(), reader_qos.get(), nullptr), what));
  waitset_ = Entity(checkEntity(dds_create_waitset(participant.participant()), what + ": creating the waitset"));
  // The read condition is a child of the reader: deleting the reader deletes it.
  const dds_entity_t condition =
      checkEntity(dds_create_readcondition(reader_.get(), DDS_ANY_STATE), what + ": creating the read condition");
  checkReturn(dds_waitset_attach(waitset_.get(), condition, 0), what + ": attaching the read condition");
}

bool ReaderBase::waitForData(std::int64_t timeout_ns) const {
  const dds_return_t triggered = dds_waitset_wait(waitset_.get(), nullptr, 0, timeout_ns);
  if (triggered < 0) checkReturn(triggered, "DDS wait on '" + name_ + "'");
  return triggered > 0;
}

std::uint32_t ReaderBase::matchedWriters() const {
  dds_subscription_matched_status_t status{};
  checkReturn(dds_get_subscription_matched_status(reader_.get(), &status), "DDS matched writers of '" + name_ + "'");
  return status.current_count;
}

}  // namespace vifusion::dds::detail
