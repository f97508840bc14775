#pragma once
// The first few pieces of bad input, each named (which record, which field, what is wrong), for the
// report; the counts in the report say how many there were in all.

#include <cstddef>
#include <string>
#include <vector>

namespace vifusion::synccheck {

class ProblemLog {
 public:
  /// Notes beyond this many are only counted: one bad sensor can produce thousands of the same problem.
  static constexpr std::size_t kMaxNotes = 20;

  explicit ProblemLog(std::vector<std::string>& notes) : notes_(notes) {}
  /// printf-style; kept while fewer than kMaxNotes are held.
  void note(const char* format, ...) __attribute__((format(printf, 2, 3)));

 private:
  std::vector<std::string>& notes_;
};

}  // namespace vifusion::synccheck
