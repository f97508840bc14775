// The other process of the two-process DDS tests:
//   dds_test_peer DOMAIN PARTITION CONFIG echo TOPIC COUNT TIMEOUT_MS
//       runs vifusion::dds::echo and exits with its code;
//   dds_test_peer DOMAIN PARTITION CONFIG pose-bytes TIMEOUT_MS
//       prints the serialised bytes of the first PoseStamped received on rt/vifusion/pose as hex.

#include <cstdio>
#include <cstdlib>
#include <string>

#include "serialised_sample.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/echo.hpp"
#include "vifusion/dds/reader.hpp"

namespace {

int usage() {
  std::fprintf(stderr,
               "usage: dds_test_peer DOMAIN PARTITION CONFIG echo TOPIC COUNT TIMEOUT_MS\n"
               "       dds_test_peer DOMAIN PARTITION CONFIG pose-bytes TIMEOUT_MS\n");
  return 64;
}

int poseBytes(const vifusion::dds::ParticipantOptions& options, std::int64_t timeout_ns) {
  vifusion::dds::Participant participant(options);
  vifusion::dds::Reader reader(participant, vifusion::dds::topics::kPose);
  const auto bytes = vifusion::dds::test::takeSerialised(reader.reader(), timeout_ns);
  if (bytes.empty()) return 1;
  for (const std::uint8_t byte : bytes) std::printf("%02x", byte);
  std::printf("\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) return usage();
  vifusion::dds::ParticipantOptions participant;
  participant.domain_id = static_cast<std::uint32_t>(std::stoul(argv[1]));
  participant.partition = argv[2];
  participant.config = argv[3];
  const std::string command = argv[4];
  try {
    if (command == "echo" && argc == 8) {
      vifusion::dds::EchoOptions options;
      options.participant = participant;
      options.topic = argv[5];
      options.count = std::stoull(argv[6]);
      options.timeout_ns = std::stoll(argv[7]) * vifusion::kNsPerMillisecond;
      return vifusion::dds::echo(options, stdout);
    }
    if (command == "pose-bytes" && argc == 6) {
      return poseBytes(participant, std::stoll(argv[5]) * vifusion::kNsPerMillisecond);
    }
  } catch (const vifusion::Error& e) {
    std::fprintf(stderr, "dds_test_peer: %s\n", e.what());
    return 2;
  }
  return usage();
}
