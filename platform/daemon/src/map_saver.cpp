#include "vifusion/daemon/map_saver.hpp"

#include "vifusion/service/log.hpp"

namespace vifusion::daemon {

MapSaver::MapSaver(std::string path, std::uint32_t surfel_capacity, std::size_t frames, SharedState& state)
    : path_(std::move(path)), state_(state) {
  snapshot_.reserve(surfel_capacity, frames);
  thread_ = std::thread([this] { run(); });
}

MapSaver::~MapSaver() {
  {
    const std::lock_guard lock(mutex_);
    quit_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

bool MapSaver::idle() const {
  const std::lock_guard lock(mutex_);
  return !pending_;
}

void MapSaver::write(std::uint64_t request_id) {
  {
    const std::lock_guard lock(mutex_);
    pending_ = true;
    request_id_ = request_id;
  }
  changed_.notify_all();
}

bool MapSaver::waitIdle() {
  std::unique_lock lock(mutex_);
  changed_.wait(lock, [this] { return !pending_; });
  return last_ok_;
}

void MapSaver::run() {
  for (;;) {
    std::uint64_t request_id = 0;
    {
      std::unique_lock lock(mutex_);
      // A pending write is finished even when asked to quit: the stop's save is the one that matters most.
      changed_.wait(lock, [this] { return pending_ || quit_; });
      if (!pending_) return;
      request_id = request_id_;
    }
    writeSnapshot(request_id);
  }
}

void MapSaver::writeSnapshot(std::uint64_t request_id) {
  bool ok = false;
  try {
    const slam::MapSaveReport report = slam::writeMapFile(snapshot_, path_);
    state_.map_file_bytes = report.bytes;
    state_.map_capture_ms = snapshot_.capture_ms;
    state_.map_write_ms = report.elapsed_ms;
    ++state_.map_saves;
    service::logLine(service::LogLevel::Info,
                     "map saved to %s: %u surfels, %d keyframes, %llu bytes (SLAM thread held %.0f ms, write %.0f ms)",
                     path_.c_str(), report.surfels, report.keyframes, static_cast<unsigned long long>(report.bytes),
                     snapshot_.capture_ms, report.elapsed_ms);
    ok = true;
  } catch (const std::exception& error) {
    ++state_.map_save_failures;
    service::logLine(service::LogLevel::Error, "map not saved (the file at %s is unchanged): %s", path_.c_str(),
                     error.what());
  }
  if (request_id > 0) state_.map_save_request_done = request_id;
  {
    const std::lock_guard lock(mutex_);
    pending_ = false;
    last_ok_ = ok;
  }
  changed_.notify_all();
}

}  // namespace vifusion::daemon
