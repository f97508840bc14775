#include "umockdev_adapter.hpp"

// clang-format off
#include <linux/ioctl.h>  // before usbdevice_fs.h, which uses _IOR without including it
#include <linux/usbdevice_fs.h>
// clang-format on
#include <umockdev.h>

#include <algorithm>
#include <cerrno>
#include <cstddef>
#include <cstring>
#include <deque>
#include <mutex>
#include <stdexcept>

#include "vifusion/core/time.hpp"
#include "vifusion/motion/adapter_command.hpp"
#include "vifusion/motion/packet_format.hpp"

namespace vifusion::usb_imu::test {
namespace {

// The node's contents are what libusb reads from a wrapped fd: the device descriptor (8086:0ad0) and one
// configuration with interface 2 and its three endpoints (bulk 0x01, bulk 0x81, interrupt 0x84), written
// from the USB 2.0 descriptor layouts (chapter 9). umockdev wants the hex in upper case.
constexpr const char* kAdapterDescription =
    "P: /devices/pci0000:00/0000:00:14.0/usb1/1-1\n"
    "N: bus/usb/001/005="
    "12010002000000408680D00A000101020301"  // device: USB 2.0, ep0 64 B, 8086:0ad0
    "0902270001010080FA"                    // configuration: 39 bytes, 1 interface
    "0904020003FF000000"                    // interface 2, 3 endpoints, vendor class
    "07050102000200"
    "07058102000200"
    "07058403000401"  // bulk OUT 0x01, bulk IN 0x81, interrupt IN 0x84
    "\n"
    "E: SUBSYSTEM=usb\nE: DEVTYPE=usb_device\nE: DEVNAME=/dev/bus/usb/001/005\nE: BUSNUM=001\nE: DEVNUM=005\n"
    "A: busnum=1\\n\nA: devnum=5\\n\nA: idVendor=8086\\n\nA: idProduct=0ad0\\n\nA: speed=480\\n\n";
constexpr unsigned kAdapterDevnum = 5;
constexpr long kUsbSpeedHigh = 3;  // enum usb_device_speed
constexpr unsigned kCapabilities = USBDEVFS_CAP_NO_PACKET_SIZE_LIM | USBDEVFS_CAP_REAP_AFTER_DISCONNECT;

}  // namespace

struct UmockdevAdapter::Impl {
  explicit Impl(const ScriptOptions& script) : device(script), start_ns(monotonicNowNs()) {}

  ScriptedMotionDevice device;
  UMockdevTestbed* testbed = nullptr;
  UMockdevIoctlBase* handler = nullptr;
  std::mutex mutex;
  std::deque<UMockdevIoctlData*> completed;  ///< OUT URBs done, waiting to be reaped
  std::deque<UMockdevIoctlData*> bulk_in;
  std::deque<UMockdevIoctlData*> interrupt_in;
  std::deque<UMockdevIoctlData*> discarded;
  std::size_t next_transfer = 0;
  std::size_t submitted = 0;
  std::int64_t start_ns;
  bool stream_started = false;
  bool unplugged = false;

  bool handle(UMockdevIoctlClient* client);
  bool submit(UMockdevIoctlClient* client, UMockdevIoctlData* arg);
  bool reap(UMockdevIoctlClient* client, UMockdevIoctlData* arg);
  bool discard(UMockdevIoctlClient* client, UMockdevIoctlData* arg);
  /// The next URB that may complete now, filled in, or null.
  UMockdevIoctlData* nextReapable();
};

namespace {

gboolean onIoctl(UMockdevIoctlBase*, UMockdevIoctlClient* client, gpointer impl) {
  return static_cast<UmockdevAdapter::Impl*>(impl)->handle(client) ? TRUE : FALSE;
}

void completeWithValue(UMockdevIoctlData* arg, std::size_t bytes, const void* value, UMockdevIoctlClient* client) {
  UMockdevIoctlData* data = umockdev_ioctl_data_resolve(arg, 0, bytes, nullptr);
  std::memcpy(data->data, value, bytes);
  umockdev_ioctl_data_unref(data);
  umockdev_ioctl_client_complete(client, 0, 0);
}

usbdevfs_urb* urbOf(UMockdevIoctlData* urb_data) { return reinterpret_cast<usbdevfs_urb*>(urb_data->data); }

}  // namespace

bool UmockdevAdapter::Impl::handle(UMockdevIoctlClient* client) {
  const unsigned long request = umockdev_ioctl_client_get_request(client);
  UMockdevIoctlData* arg = umockdev_ioctl_client_get_arg(client);
  const std::lock_guard lock(mutex);
  if (unplugged && request != USBDEVFS_REAPURB && request != USBDEVFS_REAPURBNDELAY) {
    umockdev_ioctl_client_complete(client, -1, ENODEV);
    return true;
  }
  switch (request) {
    case USBDEVFS_GET_CAPABILITIES:
      completeWithValue(arg, sizeof(kCapabilities), &kCapabilities, client);
      return true;
    case USBDEVFS_CONNECTINFO: {
      const usbdevfs_connectinfo info{.devnum = kAdapterDevnum, .slow = 0};
      completeWithValue(arg, sizeof(info), &info, client);
      return true;
    }
    case USBDEVFS_GET_SPEED:
      umockdev_ioctl_client_complete(client, kUsbSpeedHigh, 0);
      return true;
    case USBDEVFS_CLAIMINTERFACE:
    case USBDEVFS_RELEASEINTERFACE:
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    case USBDEVFS_GETDRIVER:
    case USBDEVFS_IOCTL:  // libusb's auto-detach: no kernel driver is bound to interface 2, as on the board
      umockdev_ioctl_client_complete(client, -1, ENODATA);
      return true;
    case USBDEVFS_SUBMITURB:
      return submit(client, arg);
    case USBDEVFS_REAPURB:
    case USBDEVFS_REAPURBNDELAY:
      return reap(client, arg);
    case USBDEVFS_DISCARDURB:
      return discard(client, arg);
    default:
      return false;  // ENOTTY, as for an ioctl the kernel does not know
  }
}

bool UmockdevAdapter::Impl::submit(UMockdevIoctlClient* client, UMockdevIoctlData* arg) {
  UMockdevIoctlData* urb_data = umockdev_ioctl_data_resolve(arg, 0, sizeof(usbdevfs_urb), nullptr);
  usbdevfs_urb* urb = urbOf(urb_data);
  UMockdevIoctlData* buffer =
      umockdev_ioctl_data_resolve(urb_data, offsetof(usbdevfs_urb, buffer), urb->buffer_length, nullptr);
  ++submitted;
  if (urb->endpoint == motion::kCommandOutEndpoint) {
    const auto status = device.bulkWrite(urb->endpoint, std::span(buffer->data, urb->buffer_length), 0);
    urb->actual_length = status == UsbStatus::kOk ? urb->buffer_length : 0;
    urb->status = status == UsbStatus::kOk ? 0 : -EPIPE;
    completed.push_back(urb_data);
  } else if (urb->endpoint == motion::kCommandInEndpoint) {
    bulk_in.push_back(urb_data);
  } else if (urb->endpoint == motion::kImuInterruptEndpoint) {
    // Real-time pacing starts with the stream, not with the test bed: the start sequence takes 300 ms.
    if (!stream_started) start_ns = monotonicNowNs();
    stream_started = true;
    interrupt_in.push_back(urb_data);
  } else {
    umockdev_ioctl_data_unref(buffer);
    umockdev_ioctl_data_unref(urb_data);
    umockdev_ioctl_client_complete(client, -1, EINVAL);
    return true;
  }
  umockdev_ioctl_data_unref(buffer);  // urb_data keeps its resolved child
  umockdev_ioctl_client_complete(client, 0, 0);
  return true;
}

UMockdevIoctlData* UmockdevAdapter::Impl::nextReapable() {
  const auto pop = [](std::deque<UMockdevIoctlData*>& queue) {
    UMockdevIoctlData* front = queue.front();
    queue.pop_front();
    return front;
  };
  if (!discarded.empty()) {
    UMockdevIoctlData* urb_data = pop(discarded);
    urbOf(urb_data)->status = -ENOENT;
    urbOf(urb_data)->actual_length = 0;
    return urb_data;
  }
  if (!completed.empty()) return pop(completed);
  if (unplugged) {
    // What usbfs does on disconnect: URBs still pending come back with -ESHUTDOWN, then reaping fails
    // with ENODEV. (The kernel also raises POLLERR on the fd, which a umockdev socket cannot.)
    for (auto* queue : {&bulk_in, &interrupt_in}) {
      if (!queue->empty()) {
        urbOf(queue->front())->status = -ESHUTDOWN;
        urbOf(queue->front())->actual_length = 0;
        return pop(*queue);
      }
    }
    return nullptr;
  }
  if (!bulk_in.empty()) {
    usbdevfs_urb* urb = urbOf(bulk_in.front());
    std::size_t received = 0;
    if (device.bulkRead(urb->endpoint, std::span(static_cast<std::uint8_t*>(urb->buffer), urb->buffer_length), received,
                        0) == UsbStatus::kOk) {
      urb->actual_length = static_cast<int>(received);
      urb->status = 0;
      return pop(bulk_in);
    }
  }
  if (!interrupt_in.empty() && next_transfer < device.transferCount()) {
    const std::int64_t due_ns =
        start_ns + static_cast<std::int64_t>(next_transfer) * device.options().transfer_period_ns;
    if (monotonicNowNs() < due_ns) return nullptr;
    if (device.options().unplug_after && next_transfer == *device.options().unplug_after) {
      unplugged = true;
      return nextReapable();
    }
    usbdevfs_urb* urb = urbOf(interrupt_in.front());
    const std::span<const std::uint8_t> bytes = device.transferBytes(next_transfer++);
    const std::size_t length = std::min<std::size_t>(bytes.size(), urb->buffer_length);
    std::memcpy(urb->buffer, bytes.data(), length);
    urb->actual_length = static_cast<int>(length);
    urb->status = 0;
    return pop(interrupt_in);
  }
  return nullptr;
}

bool UmockdevAdapter::Impl::reap(UMockdevIoctlClient* client, UMockdevIoctlData* arg) {
  UMockdevIoctlData* urb_data = nextReapable();
  if (urb_data == nullptr) {
    umockdev_ioctl_client_complete(client, -1, unplugged ? ENODEV : EAGAIN);
    return true;
  }
  UMockdevIoctlData* pointer = umockdev_ioctl_data_resolve(arg, 0, sizeof(void*), nullptr);
  umockdev_ioctl_data_set_ptr(pointer, 0, urb_data);
  umockdev_ioctl_data_unref(pointer);
  umockdev_ioctl_data_unref(urb_data);
  umockdev_ioctl_client_complete(client, 0, 0);
  return true;
}

bool UmockdevAdapter::Impl::discard(UMockdevIoctlClient* client, UMockdevIoctlData* arg) {
  const auto address = reinterpret_cast<gulong>(*reinterpret_cast<void**>(arg->data));
  for (auto* queue : {&bulk_in, &interrupt_in}) {
    const auto it = std::find_if(queue->begin(), queue->end(),
                                 [address](UMockdevIoctlData* urb_data) { return urb_data->client_addr == address; });
    if (it != queue->end()) {
      discarded.push_back(*it);
      queue->erase(it);
      umockdev_ioctl_client_complete(client, 0, 0);
      return true;
    }
  }
  umockdev_ioctl_client_complete(client, -1, EINVAL);
  return true;
}

UmockdevAdapter::UmockdevAdapter(const ScriptOptions& script) : impl_(std::make_unique<Impl>(script)) {
  impl_->testbed = umockdev_testbed_new();
  impl_->handler = umockdev_ioctl_base_new();
  g_signal_connect(impl_->handler, "handle-ioctl", G_CALLBACK(onIoctl), impl_.get());
  GError* error = nullptr;
  // The handler first, so the node exists with its ioctls answered when the device appears.
  if (!umockdev_testbed_attach_ioctl(impl_->testbed, kDevnode, impl_->handler, &error) ||
      !umockdev_testbed_add_from_string(impl_->testbed, kAdapterDescription, &error)) {
    const std::string message = error != nullptr ? error->message : "unknown";
    g_clear_error(&error);
    throw std::runtime_error("umockdev test bed: " + message);
  }
}

UmockdevAdapter::~UmockdevAdapter() {
  g_clear_object(&impl_->testbed);  // detaches the handler first
  g_clear_object(&impl_->handler);
  for (auto* queue : {&impl_->completed, &impl_->bulk_in, &impl_->interrupt_in, &impl_->discarded}) {
    for (UMockdevIoctlData* urb_data : *queue) umockdev_ioctl_data_unref(urb_data);
  }
}

ScriptedMotionDevice& UmockdevAdapter::device() { return impl_->device; }

std::size_t UmockdevAdapter::interruptUrbsCompleted() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->next_transfer;
}

std::size_t UmockdevAdapter::urbsSubmitted() const {
  const std::lock_guard lock(impl_->mutex);
  return impl_->submitted;
}

}  // namespace vifusion::usb_imu::test
