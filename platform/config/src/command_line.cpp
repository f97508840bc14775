#include "vifusion/config/command_line.hpp"

#include <cstdio>

#include "vifusion/config/config_keys.hpp"
#include "vifusion/config/yaml_loader.hpp"
#include "vifusion/core/version.hpp"

namespace vifusion::config {

CommandLine::CommandLine(CLI::App& app) {
  app.add_option("--config", config_path_,
                 "YAML configuration file (keys as the options below; unknown keys are errors)");
  app.add_flag("--dump-config", dump_, "Print the effective configuration as YAML and exit");
  DaemonConfig defaults;
  const std::vector<ConfigKey> keys = configKeys(defaults);
  paths_.reserve(keys.size());
  values_.resize(keys.size());
  for (std::size_t i = 0; i < keys.size(); ++i) {
    paths_.push_back(keys[i].path);
    // Text options, typed by parseValue after parsing: one type check for file and command line.
    options_.push_back(app.add_option("--" + keys[i].path, values_[i], keys[i].help)
                           ->default_str(formatValue(keys[i]))
                           ->type_name(typeName(keys[i]) == std::string("a string") ? "TEXT" : "VALUE"));
  }
}

DaemonConfig CommandLine::resolve() const {
  DaemonConfig config;
  if (!config_path_.empty()) loadYamlFile(config_path_, config);
  std::vector<ConfigKey> keys = configKeys(config);
  for (std::size_t i = 0; i < keys.size(); ++i) {
    if (options_[i]->count() > 0) parseValue(keys[i], values_[i], "command line: ");
  }
  config.validate();
  return config;
}

int parseCommandLine(CLI::App& app, CommandLine& command_line, int argc, char** argv, const char* program,
                     DaemonConfig& config) {
  app.set_version_flag("--version", std::string(program) + " " + versionString());
  try {
    app.parse(argc, argv);
  } catch (const CLI::Success& e) {  // --help or --version
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::fprintf(stderr, "%s: %s (see --help)\n", program, e.what());
    return kExitConfig;
  }
  try {
    config = command_line.resolve();
  } catch (const ConfigError& e) {
    std::fprintf(stderr, "%s: %s\n", program, e.what());
    return kExitConfig;
  }
  if (command_line.dumpRequested()) {
    std::fputs(dumpYaml(config).c_str(), stdout);
    return kExitOk;
  }
  return -1;
}

}  // namespace vifusion::config
