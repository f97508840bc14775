#include "vifusion/v4l2_scripted/scripted_v4l2_device.hpp"

#include <fcntl.h>
#include <linux/videodev2.h>
#include <sys/mman.h>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <limits>

#include "node_instance.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/v4l2/fourcc.hpp"

namespace vifusion::v4l2_scripted {
namespace {
constexpr std::int64_t kForever = std::numeric_limits<std::int64_t>::max();
constexpr short kUnpluggedEvents = POLLERR | POLLHUP;
}  // namespace

ScriptedV4l2Device::ScriptedV4l2Device(ManualClock& clock) : clock_(clock) {}

ScriptedV4l2Device::~ScriptedV4l2Device() = default;

void ScriptedV4l2Device::addNode(const ScriptedNodeConfig& config) {
  std::lock_guard lock(mutex_);
  for (const auto& existing : configs_) {
    if (existing->path == config.path) throw Error("scripted V4L2 device: node " + config.path + " added twice");
  }
  if (config.path.empty()) throw Error("scripted V4L2 device: ScriptedNodeConfig.path is empty");
  if (config.formats.empty())
    throw Error("scripted V4L2 node " + config.path + ": ScriptedNodeConfig.formats is empty");
  for (const ScriptedFormat& format : config.formats) {
    if (format.fps.empty() || format.width_px <= 0 || format.height_px <= 0 ||
        (format.bytes_per_line == 0 && v4l2::bytesPerPixel(format.fourcc) == 0)) {
      throw Error("scripted V4L2 node " + config.path +
                  ": a ScriptedFormat has no rates, no size, or bytes_per_line 0 "
                  "for a fourcc without a known pixel size");
    }
    for (int fps : format.fps) {
      if (fps <= 0)
        throw Error("scripted V4L2 node " + config.path + ": ScriptedFormat.fps holds " + std::to_string(fps));
    }
  }
  if (!config.schedule.produce) throw Error("scripted V4L2 node " + config.path + ": FrameSchedule.produce is empty");
  if (config.schedule.period_ns < 0) throw Error("scripted V4L2 node " + config.path + ": FrameSchedule.period_ns < 0");
  if (config.max_buffers < 1) throw Error("scripted V4L2 node " + config.path + ": max_buffers < 1");
  configs_.push_back(std::make_unique<ScriptedNodeConfig>(config));
  instances_.push_back(std::make_unique<NodeInstance>(*configs_.back(), *this));
  current_.push_back(instances_.back().get());
  if (!plugged_) current_.back()->markGone();
}

// ---- injection ----

void ScriptedV4l2Device::unplug() {
  std::lock_guard lock(mutex_);
  catchUp();
  unplugLocked();
}

void ScriptedV4l2Device::replug() {
  std::lock_guard lock(mutex_);
  catchUp();
  replugLocked();
}

void ScriptedV4l2Device::scheduleUnplug(std::int64_t t_ns) {
  std::lock_guard lock(mutex_);
  unplug_at_ns_ = t_ns;
}

void ScriptedV4l2Device::scheduleReplug(std::int64_t t_ns) {
  std::lock_guard lock(mutex_);
  replug_at_ns_ = t_ns;
}

void ScriptedV4l2Device::unplugLocked() {
  plugged_ = false;
  for (NodeInstance* instance : current_) instance->markGone();
}

void ScriptedV4l2Device::replugLocked() {
  for (std::size_t i = 0; i < configs_.size(); ++i) {
    current_[i]->markGone();  // a replug without an unplug still ends the old instance
    instances_.push_back(std::make_unique<NodeInstance>(*configs_[i], *this));
    current_[i] = instances_.back().get();
  }
  plugged_ = true;
}

// ---- time ----

std::optional<std::int64_t> ScriptedV4l2Device::nextEventNs() const {
  std::optional<std::int64_t> next;
  const auto consider = [&next](std::optional<std::int64_t> t_ns) {
    if (t_ns && (!next || *t_ns < *next)) next = t_ns;
  };
  for (const NodeInstance* instance : current_) consider(instance->nextArrivalNs());
  consider(unplug_at_ns_);
  consider(replug_at_ns_);
  return next;
}

void ScriptedV4l2Device::catchUp() {
  const std::int64_t now_ns = clock_.nowNs();
  while (true) {
    // Earliest frame arrival due by now; arrivals at the same instant as an unplug still happen first.
    NodeInstance* earliest = nullptr;
    std::int64_t earliest_ns = kForever;
    for (NodeInstance* instance : current_) {
      const auto arrival_ns = instance->nextArrivalNs();
      if (arrival_ns && *arrival_ns <= now_ns && *arrival_ns < earliest_ns) {
        earliest = instance;
        earliest_ns = *arrival_ns;
      }
    }
    const bool unplug_due = unplug_at_ns_ && *unplug_at_ns_ <= now_ns && *unplug_at_ns_ < earliest_ns;
    const bool replug_due = replug_at_ns_ && *replug_at_ns_ <= now_ns && *replug_at_ns_ < earliest_ns;
    if (unplug_due && (!replug_due || *unplug_at_ns_ <= *replug_at_ns_)) {
      unplug_at_ns_.reset();
      unplugLocked();
    } else if (replug_due) {
      replug_at_ns_.reset();
      replugLocked();
    } else if (earliest != nullptr) {
      earliest->deliverArrival();
    } else {
      return;
    }
  }
}

// ---- inspection ----

bool ScriptedV4l2Device::plugged() const {
  std::lock_guard lock(mutex_);
  return plugged_;
}

std::int64_t ScriptedV4l2Device::ruleViolations() const {
  std::lock_guard lock(mutex_);
  return violations_;
}

std::string ScriptedV4l2Device::lastViolation() const {
  std::lock_guard lock(mutex_);
  return std::string(last_violation_.view());
}

int ScriptedV4l2Device::openFdCount() const {
  std::lock_guard lock(mutex_);
  return static_cast<int>(files_.size());
}

int ScriptedV4l2Device::liveMappingCount() const {
  std::lock_guard lock(mutex_);
  int count = 0;
  for (const auto& instance : instances_) count += instance->liveMappings();
  return count;
}

NodeInstance* ScriptedV4l2Device::currentInstance(const std::string& path) const {
  for (std::size_t i = 0; i < configs_.size(); ++i) {
    if (configs_[i]->path == path) return current_[i];
  }
  return nullptr;
}

ScriptedNodeStats ScriptedV4l2Device::nodeStats(const std::string& path) const {
  std::lock_guard lock(mutex_);
  const NodeInstance* instance = currentInstance(path);
  if (instance == nullptr) throw Error("scripted V4L2 device: no node " + path);
  return instance->stats();
}

std::vector<std::uint8_t> ScriptedV4l2Device::controlValue(const std::string& path, std::uint8_t unit,
                                                           std::uint8_t selector) const {
  std::lock_guard lock(mutex_);
  const NodeInstance* instance = currentInstance(path);
  const ScriptedControl* control = instance != nullptr ? instance->control(unit, selector) : nullptr;
  return control != nullptr ? control->value : std::vector<std::uint8_t>{};
}

int ScriptedV4l2Device::violation(int error_number, const char* format, ...) {
  constexpr std::size_t kMessageBytes = v4l2::ProblemText::kCapacity + 1;
  char message[kMessageBytes];
  std::va_list arguments;
  va_start(arguments, format);
  std::vsnprintf(message, sizeof message, format, arguments);
  va_end(arguments);
  ++violations_;
  last_violation_.set("%s", message);
  return error_number;
}

// ---- DeviceIo ----

ScriptedV4l2Device::OpenFile* ScriptedV4l2Device::findFile(int fd) {
  for (OpenFile& file : files_) {
    if (file.fd == fd) return &file;
  }
  return nullptr;
}

int ScriptedV4l2Device::open(const char* path, int flags) {
  std::lock_guard lock(mutex_);
  catchUp();
  NodeInstance* instance = path != nullptr ? currentInstance(path) : nullptr;
  if (instance == nullptr || instance->gone()) {
    errno = ENOENT;  // unknown node, or its node file vanished with the unplug
    return -1;
  }
  const int fd = next_fd_++;
  files_.push_back(OpenFile{fd, instance, flags});
  return fd;
}

int ScriptedV4l2Device::close(int fd) {
  std::lock_guard lock(mutex_);
  catchUp();
  for (std::size_t i = 0; i < files_.size(); ++i) {
    if (files_[i].fd != fd) continue;
    files_[i].node->closeFile(fd);
    files_.erase(files_.begin() + static_cast<std::ptrdiff_t>(i));
    return 0;
  }
  errno = violation(EBADF, "close(%d): not an open scripted descriptor", fd);
  return -1;
}

int ScriptedV4l2Device::ioctl(int fd, unsigned long request, void* argument) {
  std::lock_guard lock(mutex_);
  catchUp();
  OpenFile* file = findFile(fd);
  if (file == nullptr) {
    errno = violation(EBADF, "ioctl(%d, 0x%lx): not an open scripted descriptor", fd, request);
    return -1;
  }
  if (file->node->gone()) {
    errno = ENODEV;
    return -1;
  }
  if (argument == nullptr) {
    errno = violation(EFAULT, "ioctl(%d, 0x%lx): null argument", fd, request);
    return -1;
  }
  int error = file->node->ioctl(fd, file->flags, request, argument);
  // A blocking DQBUF waits by moving the clock to the next scripted event instead of sleeping.
  const bool blocking = (file->flags & O_NONBLOCK) == 0;
  while (error == EAGAIN && request == VIDIOC_DQBUF && blocking) {
    const auto next_ns = nextEventNs();
    if (!next_ns) {
      error = violation(EDEADLK, "%s blocking DQBUF would wait forever: nothing is scheduled",
                        file->node->config().path.c_str());
      break;
    }
    clock_.advanceTo(*next_ns);
    catchUp();
    error = file->node->gone() ? ENODEV : file->node->ioctl(fd, file->flags, request, argument);
  }
  if (error != 0) {
    errno = error;
    return -1;
  }
  return 0;
}

void* ScriptedV4l2Device::mmap(void* address, std::size_t length, int protection, int flags, int fd, off_t offset) {
  (void)address;  // a hint only, as for the kernel
  std::lock_guard lock(mutex_);
  catchUp();
  OpenFile* file = findFile(fd);
  if (file == nullptr) {
    errno = violation(EBADF, "mmap(fd %d): not an open scripted descriptor", fd);
    return MAP_FAILED;
  }
  if (file->node->gone()) {
    errno = ENODEV;
    return MAP_FAILED;
  }
  void* mapping = nullptr;
  if (const int error = file->node->mmap(length, protection, flags, offset, &mapping)) {
    errno = error;
    return MAP_FAILED;
  }
  return mapping;
}

int ScriptedV4l2Device::munmap(void* address, std::size_t length) {
  std::lock_guard lock(mutex_);
  for (const auto& instance : instances_) {
    if (instance->unmap(address)) return 0;
  }
  errno = violation(EINVAL, "munmap(%p, %zu): not a scripted mapping", address, length);
  return -1;
}

short ScriptedV4l2Device::pollEvents(int fd) {
  OpenFile* file = findFile(fd);
  if (file == nullptr) {
    violation(EBADF, "poll on fd %d: not an open scripted descriptor", fd);
    return POLLNVAL;
  }
  if (file->node->gone()) return kUnpluggedEvents;
  return file->node->pollEvents();
}

int ScriptedV4l2Device::pollReady(pollfd* fds, nfds_t count) {
  int ready = 0;
  for (nfds_t i = 0; i < count; ++i) {
    // POLLERR, POLLHUP and POLLNVAL are reported whether asked for or not.
    fds[i].revents = static_cast<short>(pollEvents(fds[i].fd) & (fds[i].events | POLLERR | POLLHUP | POLLNVAL));
    if (fds[i].revents != 0) ++ready;
  }
  return ready;
}

int ScriptedV4l2Device::poll(pollfd* fds, nfds_t count, int timeout_ms) {
  std::lock_guard lock(mutex_);
  const std::int64_t deadline_ns =
      timeout_ms < 0 ? kForever : clock_.nowNs() + static_cast<std::int64_t>(timeout_ms) * kNsPerMillisecond;
  while (true) {
    catchUp();
    const int ready = pollReady(fds, count);
    if (ready > 0 || timeout_ms == 0) return ready;
    const auto next_ns = nextEventNs();
    if (!next_ns || *next_ns > deadline_ns) {
      if (deadline_ns == kForever) {
        errno = violation(EDEADLK, "poll without timeout would wait forever: nothing is scheduled");
        return -1;
      }
      clock_.advanceTo(deadline_ns);
      catchUp();
      return pollReady(fds, count);
    }
    clock_.advanceTo(*next_ns);
  }
}

}  // namespace vifusion::v4l2_scripted
