#pragma once
// `vifusion echo TOPIC`: subscribe to one of vifusion's topics (topics.hpp) with its message type and
// QoS and print every sample as one JSON line, field for field with the ROS 2 field names.

#include <cstdint>
#include <cstdio>
#include <string>

#include "vifusion/dds/participant.hpp"

namespace vifusion::dds {

/// Exit codes of echo().
inline constexpr int kEchoOk = 0;
inline constexpr int kEchoTimedOut = 1;  ///< the timeout passed before `count` samples (or any) arrived
inline constexpr int kEchoFailed = 2;    ///< unknown topic, invalid options or a DDS error

struct EchoOptions {
  /// "rt/vifusion/odometry", or the ROS 2 name "/vifusion/odometry" (a leading '/' is optional).
  std::string topic;
  /// Domain, Cyclone configuration and partition to listen on.
  ParticipantOptions participant;
  /// Stop after this many samples; 0: no limit.
  std::uint64_t count = 0;
  /// Give up this long after the start [ns]; 0: wait for ever.
  std::int64_t timeout_ns = 0;
  /// Print byte sequences (PointCloud2.data) element by element instead of their length.
  bool full_arrays = false;

  /// Throws vifusion::Error naming the field that is unusable (topic empty, timeout_ns negative,
  /// the participant options).
  void validate() const;
};

/// Prints each received sample as one line of JSON to `out` (flushed per line) and returns
///   kEchoOk        when `count` samples arrived, or with count 0, when the timeout passed after at
///                  least one sample;
///   kEchoTimedOut  when the timeout passed first;
///   kEchoFailed    for an unknown topic, invalid options or a DDS error.
/// Every failure prints one line starting "vifusion echo: " on stderr saying what went wrong (the known
/// topics, the samples received and writers matched before the timeout, …).
int echo(const EchoOptions& options, std::FILE* out);

}  // namespace vifusion::dds
