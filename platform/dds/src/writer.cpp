#include "vifusion/dds/writer.hpp"

#include "qos.hpp"

namespace vifusion::dds::detail {

WriterBase::WriterBase(const Participant& participant, const dds_topic_descriptor_t& descriptor, std::string_view name,
                       const TopicQos& qos)
    : name_(name) {
  const std::string what = "DDS writer on '" + name_ + "'";
  topic_ = Entity(checkEntity(dds_create_topic(participant.participant(), &descriptor, name_.c_str(), nullptr, nullptr),
                              what + ": creating the topic"));
  const QosPtr writer_qos = endpointQos(qos, Endpoint::Writer);
  writer_ =
      Entity(checkEntity(dds_create_writer(participant.publisher(), topic_.get(), writer_qos.get(), nullptr), what));
}

bool WriterBase::write(const void* sample) {
  const dds_return_t rc = dds_write(writer_.get(), sample);
  if (rc == DDS_RETCODE_TIMEOUT) return false;
  if (rc < 0) checkReturn(rc, "DDS write on '" + name_ + "'");  // message built only on failure
  return true;
}

std::uint32_t WriterBase::matchedReaders() const {
  dds_publication_matched_status_t status{};
  checkReturn(dds_get_publication_matched_status(writer_.get(), &status), "DDS matched readers of '" + name_ + "'");
  return status.current_count;
}

}  // namespace vifusion::dds::detail
