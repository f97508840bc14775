#pragma once
// A DDS domain participant built from an explicit Cyclone configuration, with one publisher and one
// subscriber in the configured partition.
//
// The domain is created with dds_create_domain(domain_id, config), so Cyclone reads exactly this
// configuration and never CYCLONEDDS_URI: which network interfaces DDS uses is decided by the caller's
// XML (tests: ../shared/dds/loopback.xml), not by whatever environment the process inherits. When
// that XML names one interface, every socket Cyclone opens is then bound to it in the kernel
// (socket_confinement.hpp): Cyclone 0.10 alone would receive on all interfaces.

#include <cstdint>
#include <string>

#include "vifusion/dds/entity.hpp"
#include "vifusion/dds/socket_confinement.hpp"

namespace vifusion::dds {

struct ParticipantOptions {
  /// DDS domain id; 0..232 fit Cyclone's default port mapping (7400 + 250·id + offsets).
  std::uint32_t domain_id = 0;
  /// Cyclone XML configuration: inline XML (starts with '<'), a file path or a file:// URI. Required.
  std::string config;
  /// DDS partition of every writer and reader; "" is the default partition, the only one ROS 2
  /// nodes use. Tests pick unique partitions so parallel runs cannot hear each other.
  std::string partition;

  /// Throws vifusion::Error naming the field that is unusable (domain_id range, config missing or
  /// naming a file that does not exist, partition with wildcard characters).
  void validate() const;
};

/// Owns the domain, the participant and its publisher and subscriber. One per domain and process:
/// Cyclone creates a domain once per process, so a second Participant on the same domain id throws.
/// Writers and readers must be destroyed before their Participant.
class Participant {
 public:
  /// Validates `options`, creates the entities and confines their sockets; throws vifusion::Error
  /// with Cyclone's reason on failure (Cyclone also logs configuration errors on stderr) or when
  /// the kernel refuses the confinement.
  explicit Participant(const ParticipantOptions& options);

  dds_entity_t participant() const { return participant_.get(); }
  dds_entity_t publisher() const { return publisher_.get(); }
  dds_entity_t subscriber() const { return subscriber_.get(); }
  std::uint32_t domainId() const { return domain_id_; }
  /// Which interface the DDS sockets are bound to, for the log.
  const SocketConfinement& confinement() const { return confinement_; }

 private:
  std::uint32_t domain_id_;
  // Declaration order is destruction order reversed: children go before the domain.
  Entity domain_;
  Entity participant_;
  Entity publisher_;
  Entity subscriber_;
  SocketConfinement confinement_;
};

}  // namespace vifusion::dds
