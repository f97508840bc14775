#include "problem_log.hpp"

#include <cstdarg>
#include <cstdio>

namespace vifusion::synccheck {
namespace {

constexpr std::size_t kMaxNoteLength = 200;  // one line for a person

}  // namespace

void ProblemLog::note(const char* format, ...) {
  if (notes_.size() >= kMaxNotes) return;
  char text[kMaxNoteLength];
  va_list args;
  va_start(args, format);
  std::vsnprintf(text, sizeof text, format, args);
  va_end(args);
  notes_.emplace_back(text);
}

}  // namespace vifusion::synccheck
