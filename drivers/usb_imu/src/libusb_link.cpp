#include "vifusion/usb_imu/libusb_link.hpp"

#include <fcntl.h>
#include <libusb.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <vector>

#include "vifusion/core/time.hpp"

namespace vifusion::usb_imu {
namespace {

constexpr int kNoFd = -1;
constexpr long kUsPerMs = 1000;
/// Rounds of event handling stopInterrupt() allows for cancelled transfers to come back.
constexpr int kCancelDrainRounds = 50;
constexpr int kCancelDrainRoundMs = 20;

UsbStatus toStatus(int libusb_error) {
  switch (libusb_error) {
    case LIBUSB_SUCCESS:
      return UsbStatus::kOk;
    case LIBUSB_ERROR_TIMEOUT:
      return UsbStatus::kTimeout;
    case LIBUSB_ERROR_NO_DEVICE:
    case LIBUSB_ERROR_NOT_FOUND:
      return UsbStatus::kNoDevice;
    case LIBUSB_ERROR_ACCESS:
      return UsbStatus::kAccessDenied;
    case LIBUSB_ERROR_BUSY:
      return UsbStatus::kBusy;
    case LIBUSB_ERROR_OVERFLOW:
      return UsbStatus::kOverflow;
    default:
      return UsbStatus::kIoError;
  }
}

timeval msToTimeval(int timeout_ms) {
  return {.tv_sec = timeout_ms / static_cast<int>(kUsPerMs), .tv_usec = (timeout_ms % kUsPerMs) * kUsPerMs};
}

}  // namespace

struct LibusbLink::State {
  libusb_context* context = nullptr;
  libusb_device_handle* handle = nullptr;
  int fd = kNoFd;
  int interface_number = -1;
  bool claimed = false;
  std::vector<libusb_transfer*> transfers;
  std::vector<std::vector<std::uint8_t>> buffers;
  InterruptSink* sink = nullptr;
  int in_flight = 0;
  bool stopping = false;
  bool no_device = false;
  bool io_error = false;
  bool delivered = false;

  static void LIBUSB_CALL onComplete(libusb_transfer* transfer);
};

void LIBUSB_CALL LibusbLink::State::onComplete(libusb_transfer* transfer) {
  auto* self = static_cast<State*>(transfer->user_data);
  --self->in_flight;
  switch (transfer->status) {
    case LIBUSB_TRANSFER_COMPLETED:
      self->delivered = true;
      self->sink->onInterruptTransfer(std::span<const std::uint8_t>(transfer->buffer, transfer->actual_length),
                                      monotonicNowNs());
      break;
    case LIBUSB_TRANSFER_NO_DEVICE:
      self->no_device = true;
      return;
    case LIBUSB_TRANSFER_CANCELLED:
      return;
    case LIBUSB_TRANSFER_TIMED_OUT:
      break;  // no timeout is set; resubmit anyway
    default:
      self->io_error = true;  // stall, overflow, error: the stream cannot be trusted any more
      return;
  }
  if (self->stopping) return;
  const int rc = libusb_submit_transfer(transfer);
  if (rc == LIBUSB_SUCCESS) {
    ++self->in_flight;
  } else if (toStatus(rc) == UsbStatus::kNoDevice) {
    self->no_device = true;
  } else {
    self->io_error = true;
  }
}

LibusbLink::LibusbLink(std::string devnode, std::size_t transfers_in_flight)
    : devnode_(std::move(devnode)), transfers_in_flight_(transfers_in_flight) {}

LibusbLink::~LibusbLink() { close(); }

UsbStatus LibusbLink::open(int interface_number) {
  close();
  state_ = std::make_unique<State>();
  State& s = *state_;
  s.fd = ::open(devnode_.c_str(), O_RDWR | O_CLOEXEC);
  if (s.fd == kNoFd) {
    const int error = errno;
    open_error_ = devnode_ + ": " + std::strerror(error);
    if (error == ENOENT || error == ENODEV) return UsbStatus::kNoDevice;
    return error == EACCES || error == EPERM ? UsbStatus::kAccessDenied : UsbStatus::kIoError;
  }
  // libusb 1.0.26 applies this default to contexts created afterwards (no per-context init options yet).
  libusb_set_option(nullptr, LIBUSB_OPTION_NO_DEVICE_DISCOVERY);
  int rc = libusb_init(&s.context);
  if (rc != LIBUSB_SUCCESS) return toStatus(rc);
  rc = libusb_wrap_sys_device(s.context, static_cast<intptr_t>(s.fd), &s.handle);
  if (rc != LIBUSB_SUCCESS) return toStatus(rc);
  libusb_set_auto_detach_kernel_driver(s.handle, 1);
  rc = libusb_claim_interface(s.handle, interface_number);
  if (rc != LIBUSB_SUCCESS) return toStatus(rc);
  s.interface_number = interface_number;
  s.claimed = true;
  return UsbStatus::kOk;
}

UsbStatus LibusbLink::bulkWrite(std::uint8_t endpoint, std::span<const std::uint8_t> bytes, int timeout_ms) {
  if (!state_ || state_->handle == nullptr) return UsbStatus::kNoDevice;
  int transferred = 0;
  const int rc = libusb_bulk_transfer(state_->handle, endpoint, const_cast<std::uint8_t*>(bytes.data()),
                                      static_cast<int>(bytes.size()), &transferred, timeout_ms);
  if (rc != LIBUSB_SUCCESS) return toStatus(rc);
  return static_cast<std::size_t>(transferred) == bytes.size() ? UsbStatus::kOk : UsbStatus::kIoError;
}

UsbStatus LibusbLink::bulkRead(std::uint8_t endpoint, std::span<std::uint8_t> buffer, std::size_t& received,
                               int timeout_ms) {
  received = 0;
  if (!state_ || state_->handle == nullptr) return UsbStatus::kNoDevice;
  int transferred = 0;
  const int rc = libusb_bulk_transfer(state_->handle, endpoint, buffer.data(), static_cast<int>(buffer.size()),
                                      &transferred, timeout_ms);
  received = static_cast<std::size_t>(transferred);
  return toStatus(rc);
}

UsbStatus LibusbLink::startInterrupt(std::uint8_t endpoint, std::size_t transfer_bytes, InterruptSink& sink) {
  if (!state_ || state_->handle == nullptr) return UsbStatus::kNoDevice;
  State& s = *state_;
  s.sink = &sink;
  s.stopping = false;
  s.buffers.assign(transfers_in_flight_, std::vector<std::uint8_t>(transfer_bytes));
  for (std::size_t i = 0; i < transfers_in_flight_; ++i) {
    libusb_transfer* transfer = libusb_alloc_transfer(0);
    if (transfer == nullptr) return UsbStatus::kIoError;
    s.transfers.push_back(transfer);
    libusb_fill_interrupt_transfer(transfer, s.handle, endpoint, s.buffers[i].data(), static_cast<int>(transfer_bytes),
                                   &State::onComplete, &s, 0);
    const int rc = libusb_submit_transfer(transfer);
    if (rc != LIBUSB_SUCCESS) return toStatus(rc);
    ++s.in_flight;
  }
  return UsbStatus::kOk;
}

UsbStatus LibusbLink::pumpInterrupt(int timeout_ms) {
  if (!state_ || state_->context == nullptr) return UsbStatus::kNoDevice;
  State& s = *state_;
  s.delivered = false;
  timeval timeout = msToTimeval(timeout_ms);
  const int rc = libusb_handle_events_timeout_completed(s.context, &timeout, nullptr);
  if (s.no_device) return UsbStatus::kNoDevice;
  if (rc != LIBUSB_SUCCESS && rc != LIBUSB_ERROR_INTERRUPTED) return toStatus(rc);
  if (s.io_error || s.in_flight == 0) return UsbStatus::kIoError;
  return s.delivered ? UsbStatus::kOk : UsbStatus::kTimeout;
}

void LibusbLink::stopInterrupt() {
  if (!state_) return;
  State& s = *state_;
  s.stopping = true;
  for (libusb_transfer* transfer : s.transfers) libusb_cancel_transfer(transfer);
  for (int round = 0; round < kCancelDrainRounds && s.in_flight > 0; ++round) {
    timeval timeout = msToTimeval(kCancelDrainRoundMs);
    libusb_handle_events_timeout_completed(s.context, &timeout, nullptr);
  }
  // A transfer still in flight after the drain (a wedged device) is leaked rather than freed under libusb.
  if (s.in_flight == 0) {
    for (libusb_transfer* transfer : s.transfers) libusb_free_transfer(transfer);
  }
  s.transfers.clear();
}

void LibusbLink::close() {
  if (!state_) return;
  stopInterrupt();
  State& s = *state_;
  if (s.claimed) libusb_release_interface(s.handle, s.interface_number);  // fails harmlessly after unplug
  if (s.handle != nullptr) libusb_close(s.handle);
  if (s.context != nullptr) libusb_exit(s.context);
  if (s.fd != kNoFd) ::close(s.fd);
  state_.reset();
}

}  // namespace vifusion::usb_imu
