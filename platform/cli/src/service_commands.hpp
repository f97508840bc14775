#pragma once
// `vifusion echo TOPIC`, `vifusion status` and `vifusion map save`: look at, or ask something of, a running
// vifusiond from another process (this machine or another on the robot's DDS network).
// Both find the DDS domain like the service: the daemon's YAML (--config, default
// /etc/vifusion/vifusiond.yaml when it exists), then --dds-config / --domain / --partition.

#include <cstdint>
#include <string>

namespace vifusion::cli {

struct DdsSelection {
  std::string config_file;  ///< vifusiond YAML whose dds.* keys are the defaults
  std::string dds_config;   ///< Cyclone XML (overrides dds.config)
  int domain = -1;          ///< overrides dds.domain when >= 0
  std::string partition;    ///< overrides dds.partition when non-empty
};

struct EchoCommandOptions {
  DdsSelection dds;
  std::string topic;
  std::uint64_t count = 0;  ///< 0: no limit
  double timeout_s = 0.0;   ///< 0: wait for ever
  bool full_arrays = false;
};

struct StatusCommandOptions {
  DdsSelection dds;
  double timeout_s = 3.0;
};

struct MapSaveCommandOptions {
  DdsSelection dds;
  double timeout_s = 30.0;  ///< for the service to be found and the save to end [s]
};

/// Exit codes: dds::echo's (0 received, 1 timed out, 2 bad options / DDS error).
int runEcho(const EchoCommandOptions& options);
/// Prints the service's state and the health verdict; 0 when a status arrived and every diagnostic
/// is OK, 1 when something is not OK or nothing arrived in time, 2 for bad options or a DDS error.
int runStatus(const StatusCommandOptions& options);
/// Asks the service to save its map file now (rt/vifusion/map_save_request) and waits for the answer in its
/// status. 0: saved (the file's size and the times are printed); 1: not saved (failed, no map_file configured,
/// still relocalising — the message says which) or no answer in time; 2: bad options or a DDS error.
int runMapSave(const MapSaveCommandOptions& options);

}  // namespace vifusion::cli
