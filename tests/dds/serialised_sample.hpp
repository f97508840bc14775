#pragma once
// The bytes Cyclone holds for a received sample: what arrived on the wire from a remote writer, or
// the local writer's serialisation.

#include <dds/dds.h>

#include <cstdint>
#include <vector>

namespace vifusion::dds::test {

/// The serialised form (4-byte encapsulation header + payload) of the next sample `reader` takes,
/// waiting at most timeout_ns [ns]; empty when none arrived.
std::vector<std::uint8_t> takeSerialised(dds_entity_t reader, std::int64_t timeout_ns);

}  // namespace vifusion::dds::test
