#pragma once
// vifusiond's service (DESIGN.md §1). Threads: reader (source → camera ring), SLAM (ring → pipeline →
// output ring), publisher (output ring → DDS); the calling thread handles SIGTERM/SIGINT/SIGHUP (through a
// signalfd: block them in every thread before calling) and talks to systemd. Returns the exit code:
// config/daemon_config.hpp (0 ok, 2 config, 3 source, 4 GPU, 5 DDS, 6 outputs). The log must be open.

#include <memory>

#include "vifusion/config/daemon_config.hpp"
#ifdef VIFUSION_WITH_ZR300
#include "vifusion/zr300/zr300_backend.hpp"
#endif

namespace vifusion::daemon {

int serve(const config::DaemonConfig& config);
#ifdef VIFUSION_WITH_ZR300
/// The same with the live camera reached through `backend` (null: the real devices; tests: a scripted camera).
int serve(const config::DaemonConfig& config, std::unique_ptr<zr300::Zr300Backend> backend);
#endif

}  // namespace vifusion::daemon
