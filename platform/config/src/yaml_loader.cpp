#include "vifusion/config/yaml_loader.hpp"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <set>

#include "vifusion/config/config_keys.hpp"

namespace vifusion::config {
namespace {

class Loader {
 public:
  Loader(const std::string& path, DaemonConfig& config) : path_(path), keys_(configKeys(config)) {}

  void walk(const YAML::Node& map, const std::string& prefix) {
    std::set<std::string> seen;
    for (const auto& entry : map) {
      const YAML::Node& key_node = entry.first;
      const YAML::Node& value = entry.second;
      if (!key_node.IsScalar()) fail(key_node, "a key must be a plain name");
      const std::string name = key_node.Scalar();
      const std::string path = prefix.empty() ? name : prefix + "." + name;
      if (!seen.insert(name).second) fail(key_node, "key '" + path + "' is given twice");
      if (isSection(path)) {
        if (!value.IsMap()) fail(value, "'" + path + "' must be a section (a mapping) with keys " + childNames(path));
        walk(value, path);
        continue;
      }
      const ConfigKey* key = find(path);
      if (key == nullptr) {
        const std::string suggestion = closestMatch(name, childList(prefix));
        fail(key_node, "unknown key '" + path + "'" +
                           (suggestion.empty() ? " (known: " + childNames(prefix) + ")"
                                               : " (did you mean '" + suggestion + "'?)"));
      }
      if (!value.IsScalar())
        fail(value, "key '" + path + "' must be " + typeName(*key) + ", got a " +
                        (value.IsMap()        ? "mapping"
                         : value.IsSequence() ? "list"
                                              : "null value"));
      parseValue(*key, value.Scalar(), where(value));
    }
  }

 private:
  std::string where(const YAML::Node& node) const { return path_ + ":" + std::to_string(node.Mark().line + 1) + ": "; }
  [[noreturn]] void fail(const YAML::Node& node, const std::string& message) const {
    throw ConfigError(where(node) + message);
  }
  bool isSection(const std::string& path) const {
    for (const ConfigKey& key : keys_) {
      if (key.path.size() > path.size() && key.path.starts_with(path) && key.path[path.size()] == '.') return true;
    }
    return false;
  }
  const ConfigKey* find(const std::string& path) const {
    for (const ConfigKey& key : keys_) {
      if (key.path == path) return &key;
    }
    return nullptr;
  }
  /// Names directly under `prefix` ("" = top level): keys and sections.
  std::vector<std::string> childList(const std::string& prefix) const {
    std::vector<std::string> names;
    const std::string start = prefix.empty() ? "" : prefix + ".";
    for (const ConfigKey& key : keys_) {
      if (!key.path.starts_with(start)) continue;
      const std::string rest = key.path.substr(start.size());
      const std::string name = rest.substr(0, rest.find('.'));
      if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
    }
    return names;
  }
  std::string childNames(const std::string& prefix) const {
    std::string text;
    for (const std::string& name : childList(prefix)) text += (text.empty() ? "" : ", ") + name;
    return text;
  }

  const std::string& path_;
  std::vector<ConfigKey> keys_;
};

}  // namespace

void loadYamlFile(const std::string& path, DaemonConfig& config) {
  std::ifstream file(path);
  if (!file) throw ConfigError(path + ": cannot open the configuration file (" + std::strerror(errno) + ")");
  YAML::Node root;
  try {
    root = YAML::Load(file);
  } catch (const YAML::ParserException& e) {
    throw ConfigError(path + ":" + std::to_string(e.mark.line + 1) + ": YAML syntax error: " + e.msg);
  }
  if (root.IsNull()) return;  // an empty file: every default
  if (!root.IsMap()) {
    throw ConfigError(path + ":" + std::to_string(root.Mark().line + 1) +
                      ": the configuration must be a mapping of keys (source: ..., dds: ...)");
  }
  Loader(path, config).walk(root, "");
}

}  // namespace vifusion::config
