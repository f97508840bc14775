#include "vifusion/service/log.hpp"

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <mutex>

#include "vifusion/core/error.hpp"

namespace vifusion::service {
namespace {

struct LogState {
  std::mutex mutex;
  std::string program = "vifusion";
  std::string path;
  std::FILE* file = nullptr;  // nullptr: stderr
};

LogState& state() {
  static LogState log;
  return log;
}

const char* levelName(LogLevel level) {
  switch (level) {
    case LogLevel::Info:
      return "info";
    case LogLevel::Warning:
      return "warning";
    case LogLevel::Error:
      return "error";
  }
  return "?";
}

}  // namespace

void openLog(const std::string& program, const std::string& path) {
  LogState& log = state();
  const std::lock_guard lock(log.mutex);
  log.program = program;
  log.path = path;
  if (path.empty()) return;
  log.file = std::fopen(path.c_str(), "a");
  if (log.file == nullptr)
    throw Error("log_file '" + path + "' cannot be opened for appending: " + std::strerror(errno));
}

void reopenLog() {
  LogState& log = state();
  std::unique_lock lock(log.mutex);
  if (log.path.empty()) return;
  std::FILE* file = std::fopen(log.path.c_str(), "a");
  if (file == nullptr) {
    const int error = errno;
    lock.unlock();
    logLine(LogLevel::Warning, "cannot reopen log_file '%s' (%s); still writing to the old file", log.path.c_str(),
            std::strerror(error));
    return;
  }
  std::fclose(log.file);
  log.file = file;
}

void logLine(LogLevel level, const char* format, ...) {
  char message[1024];
  va_list args;
  va_start(args, format);
  std::vsnprintf(message, sizeof(message), format, args);
  va_end(args);
  LogState& log = state();
  const std::lock_guard lock(log.mutex);
  if (log.file == nullptr) {
    std::fprintf(stderr, "%s: %s: %s\n", log.program.c_str(), levelName(level), message);
    return;
  }
  char stamp[32];
  const std::time_t now = std::time(nullptr);
  std::tm local{};
  localtime_r(&now, &local);
  std::strftime(stamp, sizeof(stamp), "%Y-%m-%dT%H:%M:%S", &local);
  std::fprintf(log.file, "%s %s: %s: %s\n", stamp, log.program.c_str(), levelName(level), message);
  std::fflush(log.file);
}

}  // namespace vifusion::service
