#include "serialised_sample.hpp"

#include <dds/ddsi/ddsi_serdata.h>

#include <chrono>
#include <thread>

#include "vifusion/core/time.hpp"

namespace vifusion::dds::test {

std::vector<std::uint8_t> takeSerialised(dds_entity_t reader, std::int64_t timeout_ns) {
  const std::int64_t deadline_ns = monotonicNowNs() + timeout_ns;
  while (monotonicNowNs() < deadline_ns) {
    ddsi_serdata* serdata = nullptr;
    dds_sample_info_t info;
    if (dds_takecdr(reader, &serdata, 1, &info, DDS_ANY_STATE) == 1) {
      // For a remote writer Cyclone keeps the received payload as it came (ddsi_serdata_default.c).
      std::vector<std::uint8_t> bytes(ddsi_serdata_size(serdata));
      ddsi_serdata_to_ser(serdata, 0, bytes.size(), bytes.data());
      ddsi_serdata_unref(serdata);
      if (info.valid_data) return bytes;
    } else {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  return {};
}

}  // namespace vifusion::dds::test
