#pragma once
// The table of configuration keys: dotted path ("dds.domain"), help text and the field it sets. The
// YAML loader, the command line and --dump-config all walk this one table, so a new field is a new
// row here and nothing else.

#include <cstdint>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "vifusion/config/daemon_config.hpp"

namespace vifusion::config {

struct ConfigKey {
  std::string path;  ///< "dds.domain"
  const char* help;
  std::variant<std::string*, std::int64_t*, std::uint32_t*, double*, bool*> field;
};

/// The keys of `config`, pointing into it, in --dump-config order.
std::vector<ConfigKey> configKeys(DaemonConfig& config);

/// The key's value as YAML scalar text (strings quoted when YAML would misread them).
std::string formatValue(const ConfigKey& key);

/// Sets the key from text (the command line, or a YAML scalar). Throws ConfigError
/// "<where>key 'path' must be <type>, got 'text'" for a value of the wrong type.
void parseValue(const ConfigKey& key, std::string_view text, std::string_view where);

/// "a number", "an integer", "true or false", "a string": for messages.
const char* typeName(const ConfigKey& key);

/// The effective configuration as a YAML document (--dump-config), nested by path.
std::string dumpYaml(DaemonConfig& config);

/// The candidate closest to `word` by edit distance, or "" when none is close enough to be a typo.
std::string closestMatch(std::string_view word, const std::vector<std::string>& candidates);

}  // namespace vifusion::config
