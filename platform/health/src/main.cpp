// vifusion-health: judges vifusiond from its rt/vifusion/status heartbeat and publishes one
// diagnostic_msgs/DiagnosticStatus per rule on rt/diagnostics every health.period_s. Its own
// WATCHDOG=1 is sent from that loop, so systemd restarts it when it can no longer judge.
// Exit codes as vifusiond (0 ok, 2 config, 5 DDS, 7 LED).

#include <chrono>
#include <csignal>
#include <cstdio>
#include <memory>

#include "diagnostics_message.hpp"
#include "health_rules.hpp"
#include "status_led.hpp"
#include "vifusion/config/command_line.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/dds/reader.hpp"
#include "vifusion/dds/writer.hpp"
#include "vifusion/service/log.hpp"
#include "vifusion/service/signal_fd.hpp"
#include "vifusion/service/systemd_notifier.hpp"

namespace vifusion::health {
namespace {

using service::LogLevel;
using service::logLine;

std::int64_t systemNowNs() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
      .count();
}

int serve(const config::DaemonConfig& config) {
  const service::SignalFd signals({SIGTERM, SIGINT, SIGHUP});
  const service::SystemdNotifier notifier;
  std::unique_ptr<StatusLed> led;
  try {
    led = std::make_unique<StatusLed>(config.health);
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "status LED: %s", error.what());
    return config::kExitLed;
  }
  std::unique_ptr<dds::Participant> participant;
  std::unique_ptr<dds::Reader<dds::msg::Status>> status_reader;
  std::unique_ptr<dds::Writer<dds::msg::DiagnosticArray>> diagnostics_writer;
  try {
    participant = std::make_unique<dds::Participant>(
        dds::ParticipantOptions{config.dds.domain, config.dds.config, config.dds.partition});
    status_reader = std::make_unique<dds::Reader<dds::msg::Status>>(*participant, dds::topics::kStatus);
    diagnostics_writer =
        std::make_unique<dds::Writer<dds::msg::DiagnosticArray>>(*participant, dds::topics::kDiagnostics);
  } catch (const std::exception& error) {
    logLine(LogLevel::Error, "DDS: %s", error.what());
    return config::kExitDds;
  }
  logLine(LogLevel::Info, "%s", participant->confinement().description.c_str());

  HealthRules rules(config.health, config.mode != "rgbd");
  DiagnosticsMessage message;
  std::array<RuleResult, kRuleCount> results;
  std::array<Level, kRuleCount> previous;
  previous.fill(Level::Ok);
  const std::int64_t period_ns = secondsToNs(config.health.period_s);
  std::int64_t next_ns = monotonicNowNs();
  notifier.ready();
  logLine(LogLevel::Info, "watching rt/vifusion/status on DDS domain %u", config.dds.domain);
  for (;;) {
    // Wait for a signal until the next judgement is due.
    const int wait_ms = static_cast<int>(std::max<std::int64_t>(0, next_ns - monotonicNowNs()) / kNsPerMillisecond);
    const int signal = signals.wait(wait_ms);
    if (signal == SIGTERM || signal == SIGINT) break;
    if (signal == SIGHUP) service::reopenLog();
    const std::int64_t now_ns = monotonicNowNs();
    if (now_ns < next_ns) continue;
    next_ns += period_ns;
    if (next_ns < now_ns) next_ns = now_ns + period_ns;  // after a pause (SIGSTOP, suspend): no burst
    try {
      while (status_reader->take([&](const dds::msg::Status& status) { rules.onStatus(status, now_ns); }) > 0) {
      }
      rules.judge(now_ns, results);
      diagnostics_writer->write(message.build(systemNowNs(), results));
    } catch (const std::exception& error) {
      logLine(LogLevel::Error, "DDS: %s", error.what());
      return config::kExitDds;
    }
    bool all_ok = true;
    for (int i = 0; i < kRuleCount; ++i) {
      all_ok = all_ok && results[i].level == Level::Ok;
      if (results[i].level != previous[i]) {  // log transitions only
        logLine(results[i].level == Level::Ok ? LogLevel::Info : LogLevel::Warning, "%s: %s", results[i].name,
                results[i].message);
        previous[i] = results[i].level;
      }
    }
    led->set(all_ok);
    notifier.status(all_ok ? "vifusiond OK" : "vifusiond NOT OK (see rt/diagnostics)");
    notifier.watchdog();  // this loop judged and published: it is alive
  }
  notifier.stopping();
  led->set(false);
  return config::kExitOk;
}

}  // namespace
}  // namespace vifusion::health

int main(int argc, char** argv) {
  using namespace vifusion;
  CLI::App app{"vifusion-health: judges vifusiond's status heartbeat and publishes rt/diagnostics"};
  config::CommandLine command_line(app);
  config::DaemonConfig config;
  if (const int code = config::parseCommandLine(app, command_line, argc, argv, "vifusion-health", config); code >= 0) {
    return code;
  }
  try {
    service::openLog("vifusion-health", config.log_file.empty() ? "" : config.log_file + ".health");
    return health::serve(config);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "vifusion-health: %s\n", error.what());
    return config::kExitConfig;
  }
}
