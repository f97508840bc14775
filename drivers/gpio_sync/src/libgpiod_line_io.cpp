#include "vifusion/gpio_sync/libgpiod_line_io.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>
#include <ctime>
#include <limits>
#include <string>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/gpio_sync/gpio_errors.hpp"

namespace vifusion::gpio_sync {
namespace {

constexpr int kMsPerSecond = 1000;

/// A kernel timespec as int64 ns, or kUnrepresentableTimeNs when it is out of range or malformed.
std::int64_t timespecToNs(const timespec& ts) {
  constexpr std::int64_t kMaxSeconds = std::numeric_limits<std::int64_t>::max() / kNsPerSecond - 1;
  if (ts.tv_nsec < 0 || ts.tv_nsec >= kNsPerSecond) return kUnrepresentableTimeNs;
  if (ts.tv_sec < -kMaxSeconds || ts.tv_sec > kMaxSeconds) return kUnrepresentableTimeNs;
  return static_cast<std::int64_t>(ts.tv_sec) * kNsPerSecond + static_cast<std::int64_t>(ts.tv_nsec);
}

EdgeType edgeType(int event_type) {
  switch (event_type) {
    case GPIOD_LINE_EVENT_RISING_EDGE:
      return EdgeType::kRising;
    case GPIOD_LINE_EVENT_FALLING_EDGE:
      return EdgeType::kFalling;
    default:
      return EdgeType::kUnknown;
  }
}

int requestEvents(gpiod_line* line, EdgeDetection edges) {
  switch (edges) {
    case EdgeDetection::kRising:
      return gpiod_line_request_rising_edge_events(line, kSyncConsumerName);
    case EdgeDetection::kFalling:
      return gpiod_line_request_falling_edge_events(line, kSyncConsumerName);
    case EdgeDetection::kBoth:
      return gpiod_line_request_both_edges_events(line, kSyncConsumerName);
  }
  errno = EINVAL;
  return -1;
}

}  // namespace

LibgpiodLineIo::LibgpiodLineIo() : raw_events_(new gpiod_line_event[kMaxEventsPerRead]) {}

LibgpiodLineIo::~LibgpiodLineIo() { close(); }

void LibgpiodLineIo::open(std::string_view chip, unsigned line_offset, EdgeDetection edges) {
  close();
  const std::string path = chipPath(chip);
  errno = 0;
  // By path, never gpiod_chip_open_lookup(): that also takes numbers and labels, so a typo could open
  // another chip; a name is /dev/<name>, which is also what gpiod_chip_open_by_name does.
  chip_ = gpiod_chip_open(path.c_str());
  if (chip_ == nullptr) throw Error(describeChipOpenFailure(chip, errno));
  const unsigned line_count = gpiod_chip_num_lines(chip_);
  if (line_offset >= line_count) {
    close();
    throw Error(describeLineOutOfRange(chip, line_offset, line_count));
  }
  line_ = gpiod_chip_get_line(chip_, line_offset);
  if (line_ == nullptr) {
    const int error_number = errno;
    close();
    throw Error(describeRequestFailure(chip, line_offset, edges, error_number, {}));
  }
  if (requestEvents(line_, edges) != 0) {
    const int error_number = errno;
    std::string holder;
    if (error_number == EBUSY && gpiod_line_update(line_) == 0 && gpiod_line_consumer(line_) != nullptr) {
      holder = gpiod_line_consumer(line_);
    }
    line_ = nullptr;  // not requested: nothing to release; the chip owns the line object
    close();
    throw Error(describeRequestFailure(chip, line_offset, edges, error_number, holder));
  }
}

LineStatus LibgpiodLineIo::waitEvent(int timeout_ms) {
  if (line_ == nullptr) return failure(EBADF);
  const timespec timeout{static_cast<std::time_t>(timeout_ms / kMsPerSecond),
                         static_cast<long>(timeout_ms % kMsPerSecond) * kNsPerMillisecond};
  const int result = gpiod_line_event_wait(line_, &timeout);
  if (result > 0) return LineStatus::kEvents;
  if (result == 0) return LineStatus::kTimeout;
  // A signal interrupting the poll is not a failure; the caller simply waits again.
  if (errno == EINTR) return LineStatus::kTimeout;
  return failure(errno);
}

LineStatus LibgpiodLineIo::readEvents(std::span<LineEvent> out, std::size_t& count) {
  count = 0;
  if (line_ == nullptr) return failure(EBADF);
  const unsigned capacity = static_cast<unsigned>(out.size() < kMaxEventsPerRead ? out.size() : kMaxEventsPerRead);
  if (capacity == 0) return LineStatus::kTimeout;
  const int read = gpiod_line_event_read_multiple(line_, raw_events_.get(), capacity);
  if (read < 0) return errno == EINTR || errno == EAGAIN ? LineStatus::kTimeout : failure(errno);
  for (int i = 0; i < read; ++i) {
    out[static_cast<std::size_t>(i)] = {timespecToNs(raw_events_[i].ts), edgeType(raw_events_[i].event_type)};
  }
  count = static_cast<std::size_t>(read);
  return count > 0 ? LineStatus::kEvents : LineStatus::kTimeout;
}

std::int64_t LibgpiodLineIo::nowNs() { return monotonicNowNs(); }

void LibgpiodLineIo::close() {
  if (line_ != nullptr) gpiod_line_release(line_);
  line_ = nullptr;
  if (chip_ != nullptr) gpiod_chip_close(chip_);
  chip_ = nullptr;
}

LineStatus LibgpiodLineIo::failure(int error_number) {
  error_text_ = std::strerror(error_number);
  return error_number == ENODEV ? LineStatus::kGone : LineStatus::kError;
}

}  // namespace vifusion::gpio_sync
