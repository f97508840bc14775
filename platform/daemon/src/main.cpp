// vifusiond: the SLAM service (DESIGN.md §1): the command line and log around daemon::serve()
// (vifusion/daemon/serve.hpp). Exit codes: config/daemon_config.hpp (0 ok, 2 config, 3 source, 4 GPU,
// 5 DDS, 6 outputs).

#include <cstdio>

#include "vifusion/config/command_line.hpp"
#include "vifusion/daemon/serve.hpp"
#include "vifusion/service/log.hpp"

int main(int argc, char** argv) {
  using namespace vifusion;
  CLI::App app{"vifusiond: dense RGB-D(-inertial) SLAM service; results over DDS, health to systemd"};
  config::CommandLine command_line(app);
  config::DaemonConfig config;
  if (const int code = config::parseCommandLine(app, command_line, argc, argv, "vifusiond", config); code >= 0) {
    return code;
  }
  try {
    service::openLog("vifusiond", config.log_file);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "vifusiond: %s\n", error.what());
    return config::kExitConfig;
  }
  try {
    return daemon::serve(config);
  } catch (const std::exception& error) {
    service::logLine(service::LogLevel::Error, "%s", error.what());
    return config::kExitConfig;
  }
}
