#pragma once
// The command line shared by vifusiond and vifusion-health: --config FILE, --dump-config and one
// option per configuration key (--source sim:living_room_0 --dds.domain 7), the defaults in --help.
// Precedence: defaults < the file < the command line.

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "vifusion/config/daemon_config.hpp"

namespace vifusion::config {

class CommandLine {
 public:
  /// Adds the options to `app`; `app` and this object must outlive parsing and resolve().
  explicit CommandLine(CLI::App& app);

  /// After app.parse(): the defaults, then --config's file, then every key given on the command
  /// line; validated. Throws ConfigError.
  DaemonConfig resolve() const;
  /// --dump-config was given: print dumpYaml(resolve()) and exit instead of running.
  bool dumpRequested() const { return dump_; }
  const std::string& configPath() const { return config_path_; }

 private:
  std::string config_path_;
  bool dump_ = false;
  std::vector<std::string> paths_;     ///< key paths, in configKeys() order
  std::vector<std::string> values_;    ///< text given on the command line, per key
  std::vector<CLI::Option*> options_;  ///< per key
};

/// Parses argv with CLI11 and resolves the configuration. Returns -1 when the program should go on
/// with `config` filled in; otherwise the exit code (0 after --help or --dump-config, kExitConfig
/// for a usage or configuration error, with a message on stderr prefixed by `program`).
int parseCommandLine(CLI::App& app, CommandLine& command_line, int argc, char** argv, const char* program,
                     DaemonConfig& config);

}  // namespace vifusion::config
