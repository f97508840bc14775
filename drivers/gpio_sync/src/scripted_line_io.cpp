#include "vifusion/gpio_sync/scripted_line_io.hpp"

#include <algorithm>
#include <chrono>
#include <limits>
#include <utility>

#include "vifusion/core/error.hpp"

namespace vifusion::gpio_sync {

ScriptedLineIo::ScriptedLineIo(std::size_t max_edges, std::int64_t start_ns)
    : max_edges_(max_edges), now_ns_(start_ns) {
  events_.reserve(max_edges);
}

void ScriptedLineIo::pushEdge(std::int64_t t_ns, EdgeType type) {
  {
    const std::lock_guard lock(mutex_);
    if (events_.size() == max_edges_) {
      throw Error("ScriptedLineIo: more than max_edges = " + std::to_string(max_edges_) + " edges queued");
    }
    events_.push_back({t_ns, type});
  }
  changed_.notify_all();
}

void ScriptedLineIo::failAfterQueued(LineStatus status, const char* text) {
  {
    const std::lock_guard lock(mutex_);
    failure_ = status;
    failure_text_ = text;
  }
  changed_.notify_all();
}

void ScriptedLineIo::failOpen(std::string message) {
  const std::lock_guard lock(mutex_);
  open_failure_ = std::move(message);
}

void ScriptedLineIo::setNowNs(std::int64_t now_ns) {
  const std::lock_guard lock(mutex_);
  now_ns_ = now_ns;
  clock_pinned_ = true;
}

bool ScriptedLineIo::isOpen() const {
  const std::lock_guard lock(mutex_);
  return open_;
}

int ScriptedLineIo::openCount() const {
  const std::lock_guard lock(mutex_);
  return open_count_;
}

std::string ScriptedLineIo::openedChip() const {
  const std::lock_guard lock(mutex_);
  return chip_;
}

unsigned ScriptedLineIo::openedLine() const {
  const std::lock_guard lock(mutex_);
  return line_offset_;
}

EdgeDetection ScriptedLineIo::openedEdges() const {
  const std::lock_guard lock(mutex_);
  return edges_;
}

std::size_t ScriptedLineIo::eventsRead() const {
  const std::lock_guard lock(mutex_);
  return next_;
}

std::size_t ScriptedLineIo::eventsPending() const {
  const std::lock_guard lock(mutex_);
  return events_.size() - next_;
}

void ScriptedLineIo::open(std::string_view chip, unsigned line_offset, EdgeDetection edges) {
  const std::lock_guard lock(mutex_);
  if (!open_failure_.empty()) {
    std::string message = std::move(open_failure_);
    open_failure_.clear();
    throw Error(message);
  }
  open_ = true;
  ++open_count_;
  chip_ = chip;
  line_offset_ = line_offset;
  edges_ = edges;
}

LineStatus ScriptedLineIo::waitEvent(int timeout_ms) {
  std::unique_lock lock(mutex_);
  const bool woken = changed_.wait_for(lock, std::chrono::milliseconds(timeout_ms),
                                       [this] { return next_ < events_.size() || failure_ != LineStatus::kEvents; });
  if (next_ < events_.size()) return LineStatus::kEvents;
  if (woken) {
    error_text_ = failure_text_;
    return failure_;
  }
  if (!clock_pinned_) now_ns_ += static_cast<std::int64_t>(timeout_ms) * kNsPerMillisecond;
  return LineStatus::kTimeout;
}

LineStatus ScriptedLineIo::readEvents(std::span<LineEvent> out, std::size_t& count) {
  const std::lock_guard lock(mutex_);
  count = std::min({out.size(), kMaxEventsPerRead, events_.size() - next_});
  for (std::size_t i = 0; i < count; ++i) {
    out[i] = events_[next_ + i];
    const std::int64_t t_ns = out[i].t_ns;
    const bool well_formed = t_ns >= 0 && t_ns <= std::numeric_limits<std::int64_t>::max() - kReadLatencyNs;
    if (!clock_pinned_ && well_formed) now_ns_ = std::max(now_ns_, t_ns + kReadLatencyNs);
  }
  next_ += count;
  return count > 0 ? LineStatus::kEvents : LineStatus::kTimeout;
}

std::int64_t ScriptedLineIo::nowNs() {
  const std::lock_guard lock(mutex_);
  return now_ns_;
}

const char* ScriptedLineIo::errorText() const {
  const std::lock_guard lock(mutex_);
  return error_text_;
}

void ScriptedLineIo::close() {
  const std::lock_guard lock(mutex_);
  open_ = false;
}

}  // namespace vifusion::gpio_sync
