#include "vifusion/usb_imu/motion_module.hpp"

#include <algorithm>
#include <chrono>
#include <utility>

#include "vifusion/core/error.hpp"
#include "vifusion/core/thread_cpu_time.hpp"

namespace vifusion::usb_imu {
namespace {

/// A step as "MMPWR=1" for messages.
std::string stepName(const motion::AdapterStep& step) {
  return std::string(motion::adapterOpcodeName(step.opcode)) + "=" + std::to_string(step.param);
}

std::unique_ptr<UsbLink> checkedLink(std::unique_ptr<UsbLink> link) {
  if (!link) throw Error("MotionModule: link is null");
  return link;
}

}  // namespace

MotionModule::MotionModule(std::unique_ptr<UsbLink> link, const MotionModuleOptions& options)
    : options_((options.validate(), options)),
      link_(checkedLink(std::move(link))),
      imu_ring_(options.imu_ring_capacity),
      frame_ring_(options.frame_event_ring_capacity),
      raw_ring_(std::max<std::size_t>(options.raw_transfer_ring_capacity, 1)),
      decoder_(options, imu_ring_, frame_ring_) {}

MotionModule::~MotionModule() { stop(); }

bool MotionModule::start() {
  stop();
  decoder_.reset();
  raw_.index = 0;
  setError({});
  const auto unplugged = [this] {
    state_.store(ModuleState::kUnplugged, std::memory_order_release);
    stop();
    return false;
  };
  const auto fail = [this](const std::string& what, UsbStatus status) {
    const std::string message = "motion module: " + what + " failed: " + std::string(usbStatusName(status));
    stop();
    setError(message);  // after stop(), whose own failures must not hide why start() failed
    throw Error(message);
  };
  UsbStatus status = link_->open(motion::kMotionInterfaceNumber);
  if (status != UsbStatus::kOk) link_->close();  // a half-open link (fd open, claim refused) lets go now
  if (status == UsbStatus::kNoDevice) return unplugged();
  if (status != UsbStatus::kOk) {
    fail("opening the adapter and claiming interface " + std::to_string(motion::kMotionInterfaceNumber), status);
  }
  opened_ = true;
  try {
    status = runSequence(motion::kStartImuSequence);
  } catch (const Error& error) {  // a bad reply: close the device before passing the error on
    const std::string message = error.what();
    stop();
    setError(message);
    throw;
  }
  if (status == UsbStatus::kNoDevice) return unplugged();
  if (status != UsbStatus::kOk) fail("the start sequence", status);
  status = link_->startInterrupt(motion::kImuInterruptEndpoint, motion::kMaxTransferBytes, *this);
  if (status == UsbStatus::kNoDevice) return unplugged();
  if (status != UsbStatus::kOk) fail("submitting the interrupt transfers on 0x84", status);
  state_.store(ModuleState::kStreaming, std::memory_order_release);
  running_.store(true, std::memory_order_release);
  thread_ = std::thread([this] { threadMain(); });
  return true;
}

void MotionModule::stop() {
  running_.store(false, std::memory_order_release);
  if (thread_.joinable()) thread_.join();
  if (!opened_) return;
  opened_ = false;
  link_->stopInterrupt();
  if (state() != ModuleState::kUnplugged) {
    try {
      // Power down so the module does not keep streaming into a closed endpoint; a vanished device is
      // fine here (runSequence returns kNoDevice), a bad reply is logged in lastError(), never thrown.
      if (runSequence(motion::kStopImuSequence) == UsbStatus::kNoDevice) {
        state_.store(ModuleState::kUnplugged, std::memory_order_release);
      }
    } catch (const Error& error) {
      setError(std::string("motion module: stop sequence: ") + error.what());
    }
  }
  link_->close();
  ModuleState expected = ModuleState::kStreaming;
  state_.compare_exchange_strong(expected, ModuleState::kClosed, std::memory_order_acq_rel);
}

std::int64_t MotionModule::threadCpuNs() const {
  return running_.load(std::memory_order_acquire) ? threadCpuTimeNs(const_cast<std::thread&>(thread_)) : 0;
}

void MotionModule::replaceLink(std::unique_ptr<UsbLink> link) {
  stop();
  link_ = checkedLink(std::move(link));
}

UsbStatus MotionModule::runStep(const motion::AdapterStep& step) {
  const std::size_t request_bytes = motion::encodeRequest(step.request(), command_buffer_);
  UsbStatus status = link_->bulkWrite(motion::kCommandOutEndpoint, std::span(command_buffer_).first(request_bytes),
                                      options_.command_timeout_ms);
  if (status != UsbStatus::kOk) return status;
  std::size_t received = 0;
  status = link_->bulkRead(motion::kCommandInEndpoint, command_buffer_, received, options_.command_timeout_ms);
  if (status != UsbStatus::kOk) return status;
  try {
    motion::decodeReply(step.opcode, std::span(command_buffer_).first(received));
  } catch (const Error& error) {
    throw Error("motion module: reply to " + stepName(step) + ": " + error.what());
  }
  if (step.wait_after_ns > 0) std::this_thread::sleep_for(std::chrono::nanoseconds(step.wait_after_ns));
  return UsbStatus::kOk;
}

template <std::size_t N>
UsbStatus MotionModule::runSequence(const std::array<motion::AdapterStep, N>& steps) {
  for (const motion::AdapterStep& step : steps) {
    const UsbStatus status = runStep(step);
    if (status != UsbStatus::kOk) {
      if (status != UsbStatus::kNoDevice) {
        setError("motion module: command " + stepName(step) + ": " + std::string(usbStatusName(status)));
      }
      return status;
    }
  }
  return UsbStatus::kOk;
}

void MotionModule::threadMain() {
  while (running_.load(std::memory_order_acquire)) {
    const UsbStatus status = link_->pumpInterrupt(options_.pump_timeout_ms);
    if (status == UsbStatus::kOk || status == UsbStatus::kTimeout) continue;
    if (status == UsbStatus::kNoDevice) {
      state_.store(ModuleState::kUnplugged, std::memory_order_release);
    } else {
      setError("motion module: interrupt transfers on 0x84 failed: " + std::string(usbStatusName(status)));
      state_.store(ModuleState::kFailed, std::memory_order_release);
    }
    return;
  }
}

void MotionModule::onInterruptTransfer(std::span<const std::uint8_t> bytes, std::int64_t host_receive_ns) {
  decoder_.decode(bytes, host_receive_ns);
  if (options_.raw_transfer_ring_capacity > 0) {
    raw_.host_receive_ns = host_receive_ns;
    raw_.size = std::min(bytes.size(), raw_.bytes.size());
    std::copy_n(bytes.begin(), raw_.size, raw_.bytes.begin());
    raw_ring_.tryPush(raw_);  // a full ring counts an overrun: the recorder is behind
    ++raw_.index;
  }
}

MotionModuleStats MotionModule::stats() const {
  MotionModuleStats out = decoder_.stats();
  out.state = state();
  return out;
}

std::string MotionModule::lastError() const {
  const std::lock_guard lock(error_mutex_);
  return last_error_;
}

void MotionModule::setError(std::string message) {
  const std::lock_guard lock(error_mutex_);
  last_error_ = std::move(message);
}

}  // namespace vifusion::usb_imu
