#include "umockdev_gpio_chip.hpp"

#include <fcntl.h>
#include <linux/gpio.h>
#include <umockdev.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>
#include <mutex>
#include <stdexcept>

namespace vifusion::gpio_sync::test {
namespace {

// A gpiochip as sysfs shows it: the node's major:minor in `dev`, which libgpiod compares with the node's.
constexpr const char* kChipDescription =
    "P: /devices/platform/gpio-sim.0/gpiochip0\n"
    "N: gpiochip0\n"
    "E: SUBSYSTEM=gpio\nE: DEVNAME=/dev/gpiochip0\nE: MAJOR=254\nE: MINOR=0\n"
    "A: dev=254:0\\n\n";
constexpr const char* kDevnode = "/dev/gpiochip0";
constexpr const char* kChipLabel = "gpio-sim";

void copyName(char (&to)[GPIO_MAX_NAME_SIZE], const char* from) {
  std::strncpy(to, from, GPIO_MAX_NAME_SIZE - 1);
  to[GPIO_MAX_NAME_SIZE - 1] = '\0';
}

}  // namespace

struct UmockdevGpioChip::Impl {
  UMockdevTestbed* testbed = nullptr;
  UMockdevIoctlBase* handler = nullptr;
  mutable std::mutex mutex;
  std::array<int, 2> event_pipe{-1, -1};
  unsigned requested_line = 0;
  std::uint32_t requested_flags = 0;
  std::string requested_consumer;
  int event_requests = 0;

  bool handle(UMockdevIoctlClient* client);
};

namespace {

gboolean onIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer impl) {
  return static_cast<UmockdevGpioChip::Impl*>(impl)->handle(client) ? TRUE : FALSE;
}

}  // namespace

bool UmockdevGpioChip::Impl::handle(UMockdevIoctlClient* client) {
  const unsigned long request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  const std::lock_guard lock(mutex);
  switch (request) {
    case GPIO_GET_CHIPINFO_IOCTL: {
      UMockdevIoctlData* data = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpiochip_info), nullptr);
      auto* info = reinterpret_cast<gpiochip_info*>(data->data);
      copyName(info->name, kChipName);
      copyName(info->label, kChipLabel);
      info->lines = kLineCount;
      umockdev_ioctl_data_unref(data);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    case GPIO_GET_LINEINFO_IOCTL: {
      UMockdevIoctlData* data = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpioline_info), nullptr);
      auto* info = reinterpret_cast<gpioline_info*>(data->data);
      if (info->line_offset >= kLineCount) {
        umockdev_ioctl_data_unref(data);
        umockdev_ioctl_client_complete(client, -1, EINVAL);
        return true;
      }
      info->flags = info->line_offset == kBusyLine ? GPIOLINE_FLAG_KERNEL : 0;
      copyName(info->name, "");
      copyName(info->consumer, info->line_offset == kBusyLine ? kBusyConsumer : "");
      umockdev_ioctl_data_unref(data);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    case GPIO_GET_LINEEVENT_IOCTL: {
      UMockdevIoctlData* data = umockdev_ioctl_data_resolve(arg, 0, sizeof(gpioevent_request), nullptr);
      auto* event_request = reinterpret_cast<gpioevent_request*>(data->data);
      if (event_request->lineoffset >= kLineCount || event_request->lineoffset == kBusyLine) {
        umockdev_ioctl_data_unref(data);
        umockdev_ioctl_client_complete(client, -1, event_request->lineoffset == kBusyLine ? EBUSY : EINVAL);
        return true;
      }
      for (int& fd : event_pipe) {
        if (fd >= 0) ::close(fd);
        fd = -1;
      }
      if (::pipe2(event_pipe.data(), O_CLOEXEC) != 0) {
        umockdev_ioctl_data_unref(data);
        umockdev_ioctl_client_complete(client, -1, errno);
        return true;
      }
      requested_line = event_request->lineoffset;
      requested_flags = event_request->eventflags;
      requested_consumer = event_request->consumer_label;
      ++event_requests;
      // The reader owns the read end from here (libgpiod closes it on release), as with the kernel's fd.
      event_request->fd = event_pipe[0];
      event_pipe[0] = -1;
      umockdev_ioctl_data_unref(data);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
    default:
      return false;  // ENOTTY, as for an ioctl the kernel does not know
  }
}

UmockdevGpioChip::UmockdevGpioChip() : impl_(std::make_unique<Impl>()) {
  impl_->testbed = umockdev_testbed_new();
  impl_->handler = umockdev_ioctl_base_new();
  g_signal_connect(impl_->handler, "handle-ioctl", G_CALLBACK(onIoctl), impl_.get());
  GError* error = nullptr;
  if (!umockdev_testbed_attach_ioctl(impl_->testbed, kDevnode, impl_->handler, &error) ||
      !umockdev_testbed_add_from_string(impl_->testbed, kChipDescription, &error)) {
    const std::string message = error != nullptr ? error->message : "unknown";
    g_clear_error(&error);
    throw std::runtime_error("umockdev test bed: " + message);
  }
}

UmockdevGpioChip::~UmockdevGpioChip() {
  g_clear_object(&impl_->testbed);
  g_clear_object(&impl_->handler);
  for (int fd : impl_->event_pipe) {
    if (fd >= 0) ::close(fd);
  }
}

void UmockdevGpioChip::emitEdge(std::uint64_t t_ns, bool rising, std::uint32_t raw_id) {
  gpioevent_data event{};
  event.timestamp = t_ns;
  event.id = raw_id != 0 ? raw_id : (rising ? GPIOEVENT_EVENT_RISING_EDGE : GPIOEVENT_EVENT_FALLING_EDGE);
  const std::lock_guard lock(impl_->mutex);
  if (impl_->event_pipe[1] < 0 || ::write(impl_->event_pipe[1], &event, sizeof(event)) != sizeof(event)) {
    throw std::runtime_error("UmockdevGpioChip: no event line requested, or the pipe is full");
  }
}

void UmockdevGpioChip::hangUp() {
  const std::lock_guard lock(impl_->mutex);
  if (impl_->event_pipe[1] >= 0) ::close(impl_->event_pipe[1]);
  impl_->event_pipe[1] = -1;
}

unsigned UmockdevGpioChip::requestedLine() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->requested_line;
}

std::uint32_t UmockdevGpioChip::requestedEventFlags() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->requested_flags;
}

std::string UmockdevGpioChip::requestedConsumer() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->requested_consumer;
}

int UmockdevGpioChip::eventRequests() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->event_requests;
}

}  // namespace vifusion::gpio_sync::test
