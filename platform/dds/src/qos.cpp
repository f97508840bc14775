#include "qos.hpp"

namespace vifusion::dds::detail {
namespace {

// How long a reliable writer may block when a slow reader keeps its history full before write()
// reports the sample as dropped: short, so a stalled viewer cannot stall the publisher thread.
constexpr dds_duration_t kMaxBlockingTime = DDS_MSECS(10);

}  // namespace

QosPtr endpointQos(const TopicQos& topic, Endpoint endpoint) {
  QosPtr qos(dds_create_qos(), &dds_delete_qos);
  dds_qset_reliability(qos.get(), DDS_RELIABILITY_RELIABLE, kMaxBlockingTime);
  dds_qset_history(qos.get(), DDS_HISTORY_KEEP_LAST, topic.depth);
  if (topic.durability == Durability::TransientLocal) {
    dds_qset_durability(qos.get(), DDS_DURABILITY_TRANSIENT_LOCAL);
    // Cyclone serves late joiners from the durability service's history, so it gets the same depth.
    dds_qset_durability_service(qos.get(), 0, DDS_HISTORY_KEEP_LAST, topic.depth, DDS_LENGTH_UNLIMITED,
                                DDS_LENGTH_UNLIMITED, DDS_LENGTH_UNLIMITED);
  } else {
    dds_qset_durability(qos.get(), DDS_DURABILITY_VOLATILE);
  }
  // Cyclone 0.10 serialises with the FIRST representation of the writer's list and, when none is
  // set, picks XCDR1 for types that allow it: @final types without @optional members (dds_writer.c,
  // dds_ensure_valid_data_representation). Stating XCDR1 alone makes that explicit and turns an IDL
  // change that needs XCDR2 (appendable, mutable, optional) into a creation error here instead of
  // samples ROS 2 (Humble, Iron: XCDR1 only) silently cannot read.
  const dds_data_representation_id_t xcdr1[] = {DDS_DATA_REPRESENTATION_XCDR1};
  dds_qset_data_representation(qos.get(), 1, xcdr1);
  if (endpoint == Endpoint::Writer) {
    // Keyless topics have one instance; as rmw_cyclonedds, do not dispose it when the writer goes.
    dds_qset_writer_data_lifecycle(qos.get(), false);
  }
  return qos;
}

}  // namespace vifusion::dds::detail
