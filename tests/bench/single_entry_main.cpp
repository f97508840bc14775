#include "single_entry_main.hpp"

#include <cstdio>
#include <exception>

namespace vifusion::bench {

int runSingleEntry(int argc, char** argv, const SingleEntry& entry) {
  try {
    if (entry.parse_own_flags != nullptr) entry.parse_own_flags(argc, argv);
    parseOptions(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", entry.program, e.what());
    return 2;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  try {
    const Size size = options().sizes.front();
    benchmark::AddCustomContext("sequence", std::string("sim:") + kPreset + ", " + std::to_string(options().frames) +
                                                " frames" + entry.sequence_note);
    benchmark::internal::Benchmark* registered =
        benchmark::RegisterBenchmark((std::string(entry.family) + "/" + size.name()).c_str(), entry.run, size)
            ->Iterations(1)
            ->Unit(entry.unit);
    if (entry.real_time) registered->UseRealTime();
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: %s\n", entry.program, e.what());
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}

}  // namespace vifusion::bench
