#include "vifusion/gpio_sync/problem_note.hpp"

#include <cstdarg>
#include <cstdio>

namespace vifusion::gpio_sync {

void ProblemNote::set(const char* format, ...) {
  const std::lock_guard lock(mutex_);
  va_list args;
  va_start(args, format);
  const int written = std::vsnprintf(text_.data(), text_.size(), format, args);
  va_end(args);
  if (written < 0) text_[0] = '\0';  // an encoding error: no text rather than a half-formatted one
}

void ProblemNote::clear() {
  const std::lock_guard lock(mutex_);
  text_[0] = '\0';
}

std::string ProblemNote::text() const {
  const std::lock_guard lock(mutex_);
  return std::string(text_.data());
}

}  // namespace vifusion::gpio_sync
