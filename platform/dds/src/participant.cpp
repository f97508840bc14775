#include "vifusion/dds/participant.hpp"

#include <filesystem>
#include <memory>
#include <set>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::dds {
namespace {

// Highest domain id whose ports fit in 16 bits with Cyclone's default port mapping.
constexpr std::uint32_t kMaxDomainId = 232;

using QosPtr = std::unique_ptr<dds_qos_t, decltype(&dds_delete_qos)>;

// No partition QoS at all for the default partition, exactly as ROS 2 nodes create theirs.
QosPtr partitionQos(const std::string& partition) {
  QosPtr qos(dds_create_qos(), &dds_delete_qos);
  if (!partition.empty()) dds_qset_partition1(qos.get(), partition.c_str());
  return qos;
}

std::string describeConfig(const std::string& config) {
  return config.starts_with('<') ? std::string("the inline XML configuration") : "configuration '" + config + "'";
}

}  // namespace

void ParticipantOptions::validate() const {
  if (domain_id > kMaxDomainId) {
    throw Error("DDS option 'domain_id' = " + std::to_string(domain_id) + " must be in 0.." +
                std::to_string(kMaxDomainId));
  }
  if (config.empty()) {
    throw Error("DDS option 'config' is empty: give the Cyclone XML (inline, a file or a file:// URI)");
  }
  if (!config.starts_with('<')) {
    const std::string path = config.starts_with("file://") ? config.substr(7) : config;
    if (!std::filesystem::is_regular_file(path)) {
      throw Error("DDS option 'config': no Cyclone configuration file '" + path + "'");
    }
  }
  if (partition.find_first_of("*?[]") != std::string::npos) {
    throw Error("DDS option 'partition' = '" + partition + "' must not contain wildcards (* ? [ ])");
  }
}

Participant::Participant(const ParticipantOptions& options) : domain_id_(options.domain_id) {
  options.validate();
  const std::string where = "DDS domain " + std::to_string(options.domain_id);
  const std::set<int> sockets_before = udpSocketDescriptors();
  const dds_entity_t domain = dds_create_domain(options.domain_id, options.config.c_str());
  if (domain == DDS_RETCODE_PRECONDITION_NOT_MET) {
    throw Error(where + " already exists in this process: use one Participant per domain");
  }
  domain_ = Entity(checkEntity(domain, where + " with " + describeConfig(options.config)));
  participant_ = Entity(
      checkEntity(dds_create_participant(options.domain_id, nullptr, nullptr), where + ": creating the participant"));
  const QosPtr qos = partitionQos(options.partition);
  publisher_ = Entity(
      checkEntity(dds_create_publisher(participant_.get(), qos.get(), nullptr), where + ": creating the publisher"));
  subscriber_ = Entity(
      checkEntity(dds_create_subscriber(participant_.get(), qos.get(), nullptr), where + ": creating the subscriber"));
  confinement_ = confineNewUdpSockets(sockets_before);
}

}  // namespace vifusion::dds
