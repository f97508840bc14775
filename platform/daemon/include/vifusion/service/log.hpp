#pragma once
// The service log: one line per event ("vifusiond: error: source 'dataset:/x' ended: rgb/12.png is
// truncated"), to stderr (the journal under systemd, which adds the time) or to a file with a time
// stamp, reopened on SIGHUP for logrotate. Thread-safe; not for the per-frame path.

#include <string>

namespace vifusion::service {

enum class LogLevel { Info, Warning, Error };

/// Sets the program name and the destination ("" = stderr). Throws vifusion::Error when the file
/// cannot be opened for appending.
void openLog(const std::string& program, const std::string& path);
/// Reopens the log file (after logrotate moved it); keeps the old one if that fails, and says so.
void reopenLog();
void logLine(LogLevel level, const char* format, ...) __attribute__((format(printf, 2, 3)));

}  // namespace vifusion::service
