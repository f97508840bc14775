#include "vifusion/gpio_sync/sync_line.hpp"

#include <span>
#include <utility>

#include "vifusion/core/error.hpp"

namespace vifusion::gpio_sync {
namespace {

std::unique_ptr<GpioLineIo> checkedIo(std::unique_ptr<GpioLineIo> io) {
  if (!io) throw Error("SyncLine: io is null");
  return io;
}

const SyncLineOptions& validated(const SyncLineOptions& options) {
  options.validate();
  return options;
}

std::string lineNameOf(const SyncLineOptions& options) {
  return options.chip + " line " + std::to_string(options.line_offset);
}

}  // namespace

SyncLine::SyncLine(std::unique_ptr<GpioLineIo> io, const SyncLineOptions& options)
    : options_(validated(options)),
      io_(checkedIo(std::move(io))),
      ring_(options.ring_capacity),
      decoder_(lineNameOf(options), options, ring_, problems_) {}

SyncLine::~SyncLine() { stop(); }

void SyncLine::start() {
  stop();
  decoder_.reset();
  errors_.clear();
  io_->open(options_.chip, static_cast<unsigned>(options_.line_offset), options_.edges);
  opened_ = true;
  state_.store(SyncLineState::kRunning, std::memory_order_release);
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] { threadMain(); });
}

void SyncLine::stop() {
  running_.store(false, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  if (!opened_) return;
  opened_ = false;
  io_->close();
  SyncLineState expected = SyncLineState::kRunning;
  state_.compare_exchange_strong(expected, SyncLineState::kClosed, std::memory_order_acq_rel);
}

void SyncLine::threadMain() {
  while (running_.load(std::memory_order_acquire)) {
    const LineStatus waited = io_->waitEvent(options_.wait_timeout_ms);
    if (waited == LineStatus::kEvents) {
      std::size_t count = 0;
      const LineStatus read = io_->readEvents(events_, count);
      if (read != LineStatus::kEvents && read != LineStatus::kTimeout) {
        endStream(read, "reading edge events");
        return;
      }
      // The read time comes after the read, so every genuine edge in the batch is at or before it.
      decoder_.decode(std::span(events_).first(count), io_->nowNs());
    } else if (waited != LineStatus::kTimeout) {
      endStream(waited, "waiting for edge events");
      return;
    }
    decoder_.publishRate(io_->nowNs());
  }
}

void SyncLine::endStream(LineStatus status, const char* step) {
  errors_.set("%s: %s failed: %s (%s)", decoder_.lineName().c_str(), step, lineStatusName(status).data(),
              io_->errorText());
  state_.store(status == LineStatus::kGone ? SyncLineState::kGone : SyncLineState::kFailed, std::memory_order_release);
}

SyncLineStats SyncLine::stats() const {
  SyncLineStats out = decoder_.stats();
  out.state = state();
  return out;
}

}  // namespace vifusion::gpio_sync
