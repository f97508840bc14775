#pragma once
// recoverMcap: the future `vifusion record --recover FILE`. Reads what McapReader can of a recording that
// was cut (SIGKILL, power loss, full disk) or damaged, and writes it as a new, complete file with a fresh
// summary, so that every tool (ros2 bag, Foxglove, indexed readers) opens it.

#include <cstdint>
#include <string>

#include "vifusion/mcap/mcap_writer_options.hpp"

namespace vifusion::mcap {

struct RecoveryResult {
  std::uint64_t messages = 0;     ///< messages copied
  std::uint64_t chunks_read = 0;  ///< chunks of the input they came from
  std::uint64_t chunks_written = 0;
  std::uint64_t schemas = 0;
  std::uint64_t channels = 0;
  std::uint64_t attachments = 0;
  std::uint64_t bytes_written = 0;
  std::uint64_t chunks_skipped = 0;  ///< corrupt chunks of an input whose summary was intact
  /// True when the input's data was whole (its summary usable or its scan reaching DataEnd) and no chunk
  /// was skipped: the output then holds everything the input held.
  bool input_complete = false;
  /// Where and why the input's data stopped (McapReader::note()) and any chunk skipped; empty when complete.
  std::string note;
};

/// Copies schemas, channels, attachments and messages (in file order) from `path_in` to a new file at
/// `path_out`, with `options` for the writer (max_message_bytes and max_channels are raised to what the
/// input needs). Channels and schemas keep their ids when the input numbers them 1, 2, ... (vifusion's
/// writer does); otherwise they are renumbered in that order.
/// @throws vifusion::Error when the input is not MCAP, path_out is path_in, or the output cannot be written.
RecoveryResult recoverMcap(const std::string& path_in, const std::string& path_out, McapWriterOptions options = {});

}  // namespace vifusion::mcap
