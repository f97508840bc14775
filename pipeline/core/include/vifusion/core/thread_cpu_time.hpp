#pragma once
// CPU time of one thread (POSIX per-thread CPU clocks): how benchmarks and the status report what a
// driver thread costs, as opposed to the wall time it spends waiting.

#include <cstdint>
#include <thread>

namespace vifusion {

/// CPU time `thread` (running, joinable) has used so far [ns]; 0 if its clock cannot be read.
std::int64_t threadCpuTimeNs(std::thread& thread);
/// CPU time the calling thread has used so far [ns].
std::int64_t currentThreadCpuTimeNs();

}  // namespace vifusion
