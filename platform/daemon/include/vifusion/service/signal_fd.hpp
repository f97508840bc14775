#pragma once
// Signals as file-descriptor events (signalfd(2)): the main thread polls them with its other work,
// so no handler runs at an arbitrary point of an arbitrary thread.

#include <initializer_list>

namespace vifusion::service {

class SignalFd {
 public:
  /// Blocks `signals` in the calling thread and opens a signalfd for them. Construct it before any
  /// thread starts: threads inherit the mask, so the signals reach only this descriptor.
  /// Throws vifusion::Error when the descriptor cannot be created.
  explicit SignalFd(std::initializer_list<int> signals);
  ~SignalFd();
  SignalFd(const SignalFd&) = delete;
  SignalFd& operator=(const SignalFd&) = delete;

  /// Waits up to `timeout_ms` [ms] and returns the signal received, or 0 if none.
  int wait(int timeout_ms) const;

 private:
  int fd_ = -1;
};

}  // namespace vifusion::service
