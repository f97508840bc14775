#include "vifusion/v4l2/problem_text.hpp"

#include <cstdarg>
#include <cstdio>

namespace vifusion::v4l2 {

void ProblemText::set(const char* format, ...) {
  std::va_list arguments;
  va_start(arguments, format);
  const int written = std::vsnprintf(text_.data(), text_.size(), format, arguments);
  va_end(arguments);
  // vsnprintf reports the untruncated length; keep what fits (a negative result means an encoding error).
  length_ =
      written < 0 ? 0 : (static_cast<std::size_t>(written) < kCapacity ? static_cast<std::size_t>(written) : kCapacity);
  text_[length_] = '\0';
}

}  // namespace vifusion::v4l2
