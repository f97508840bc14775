#pragma once
// Loads the YAML configuration file into a DaemonConfig. Strict: every key must be one of
// configKeys(), every value of its type; anything else is a ConfigError naming file, line and key,
// e.g. "vifusiond.yaml:12: unknown key 'dds.domian' (did you mean 'domain'?)".

#include <string>

#include "vifusion/config/daemon_config.hpp"

namespace vifusion::config {

/// Overwrites the fields named in `path`; keys not in the file keep their current value.
/// Throws ConfigError for a missing/unreadable file, a YAML syntax error, an unknown or duplicated
/// key, a section given as a scalar, or a value of the wrong type. Does not call validate().
void loadYamlFile(const std::string& path, DaemonConfig& config);

}  // namespace vifusion::config
