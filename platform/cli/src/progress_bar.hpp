#pragma once
// A progress bar on stderr for runs longer than a second, shown only when stderr is a terminal,
// so pipes, logs and CI output carry results and errors only.

#include <chrono>
#include <cstdint>
#include <string>

namespace vifusion::cli {

class ProgressBar {
 public:
  ProgressBar(std::string label, int64_t total);
  ~ProgressBar();
  ProgressBar(const ProgressBar&) = delete;
  ProgressBar& operator=(const ProgressBar&) = delete;

  /// Reports `done` of `total` items; redraws at most ten times a second.
  void update(int64_t done);

 private:
  std::string label_;
  int64_t total_;
  bool enabled_;
  bool drawn_ = false;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_draw_;
};

}  // namespace vifusion::cli
