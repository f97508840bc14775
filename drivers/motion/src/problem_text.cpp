#include "vifusion/motion/problem_text.hpp"

#include <cstdio>

namespace vifusion::motion {

void ProblemText::append(const char* format, ...) {
  const std::size_t room = kCapacity - length_;  // includes the terminating NUL vsnprintf writes
  if (room <= 1) return;
  va_list arguments;
  va_start(arguments, format);
  const int written = std::vsnprintf(chars_.data() + length_, room, format, arguments);
  va_end(arguments);
  if (written <= 0) return;
  // vsnprintf returns the length it wanted; only room − 1 characters were stored.
  const std::size_t stored = static_cast<std::size_t>(written) < room ? static_cast<std::size_t>(written) : room - 1;
  length_ += stored;
}

}  // namespace vifusion::motion
