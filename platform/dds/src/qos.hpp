#pragma once
// QoS of vifusion's writers and readers from a topic's TopicQos (platform.md §2.3, rmw_cyclonedds'
// create_readwrite_qos as the model).

#include <dds/dds.h>

#include <memory>

#include "vifusion/dds/topics.hpp"

namespace vifusion::dds::detail {

using QosPtr = std::unique_ptr<dds_qos_t, decltype(&dds_delete_qos)>;

enum class Endpoint : std::uint8_t { Writer, Reader };

/// RELIABLE, KEEP_LAST(depth), the topic's durability and data representation XCDR1 only.
QosPtr endpointQos(const TopicQos& topic, Endpoint endpoint);

}  // namespace vifusion::dds::detail
