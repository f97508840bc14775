#pragma once
// The main() of a benchmark with one entry run once at the first --sizes size (bench_recording, bench_map_growth,
// bench_map_save): the program's own flags, then bench_options' and Google Benchmark's, then "FAMILY/WxH".

#include <benchmark/benchmark.h>

#include <string>

#include "bench_options.hpp"

namespace vifusion::bench {

struct SingleEntry {
  const char* program = "";                         ///< for error messages
  const char* family = "";                          ///< the entry is "<family>/<W>x<H>"
  void (*parse_own_flags)(int&, char**) = nullptr;  ///< takes the program's own flags out of argv (may throw Error)
  void (*run)(benchmark::State&, Size) = nullptr;
  benchmark::TimeUnit unit = benchmark::kSecond;
  bool real_time = true;      ///< report wall time (the entry runs threads of its own)
  std::string sequence_note;  ///< appended to the "sequence" context after the frame count
};

/// Set options()' defaults before calling. Exit codes: 0, 1 (the entry failed), 2 (bad flags).
int runSingleEntry(int argc, char** argv, const SingleEntry& entry);

}  // namespace vifusion::bench
