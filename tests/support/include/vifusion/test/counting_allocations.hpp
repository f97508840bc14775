#pragma once
// Counts C++ heap allocations (operator new) made anywhere in this test executable, so a test can
// prove that a stretch of code, such as the per-frame path, allocates nothing on the host.

#include <cstdint>

namespace vifusion::test {

uint64_t heapAllocationCount();

}  // namespace vifusion::test
