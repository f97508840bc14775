#pragma once
// What the DDS tests share: a participant on loopback in a domain and partition of its own, the
// other process of the two-process tests.

#include <sys/types.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "vifusion/dds/participant.hpp"

namespace vifusion::dds::test {

/// ../shared/dds/loopback.xml, a random domain id in 1..200 and a partition unique to this call.
ParticipantOptions loopbackOptions();

/// Runs dds_test_peer with `args`, its stdout and stderr going to files read back afterwards.
class PeerProcess {
 public:
  explicit PeerProcess(const std::vector<std::string>& args);
  PeerProcess(const PeerProcess&) = delete;
  PeerProcess& operator=(const PeerProcess&) = delete;
  /// Kills the peer if it still runs and removes its output files.
  ~PeerProcess();

  /// True while the peer runs.
  bool running();
  /// Waits for the peer to end and returns its exit code (128 + signal if killed).
  int wait();
  std::string out() const;
  std::string err() const;

 private:
  std::filesystem::path dir_;
  pid_t pid_ = -1;
  int status_ = 0;
};

/// The arguments that give the peer the same domain, partition and configuration as `options`.
std::vector<std::string> peerParticipantArgs(const ParticipantOptions& options);

}  // namespace vifusion::dds::test
