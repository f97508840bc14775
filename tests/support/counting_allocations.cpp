#include "vifusion/test/counting_allocations.hpp"

#include <atomic>
#include <cstdlib>
#include <new>

namespace vifusion::test {
namespace {
std::atomic<uint64_t> g_allocations{0};
}  // namespace

uint64_t heapAllocationCount() { return g_allocations.load(); }

}  // namespace vifusion::test

// Replacements of the global allocation functions ([new.delete]); the aligned and nothrow forms
// forward here or are counted the same way.
void* operator new(std::size_t bytes) {
  ++vifusion::test::g_allocations;
  if (void* pointer = std::malloc(bytes == 0 ? 1 : bytes)) return pointer;
  throw std::bad_alloc();
}
void* operator new[](std::size_t bytes) { return operator new(bytes); }
void* operator new(std::size_t bytes, std::align_val_t alignment) {
  ++vifusion::test::g_allocations;
  const std::size_t align = static_cast<std::size_t>(alignment);
  if (void* pointer = std::aligned_alloc(align, (bytes + align - 1) / align * align)) return pointer;
  throw std::bad_alloc();
}
void* operator new[](std::size_t bytes, std::align_val_t alignment) { return operator new(bytes, alignment); }
void operator delete(void* pointer) noexcept { std::free(pointer); }
void operator delete[](void* pointer) noexcept { std::free(pointer); }
void operator delete(void* pointer, std::size_t) noexcept { std::free(pointer); }
void operator delete[](void* pointer, std::size_t) noexcept { std::free(pointer); }
void operator delete(void* pointer, std::align_val_t) noexcept { std::free(pointer); }
void operator delete[](void* pointer, std::align_val_t) noexcept { std::free(pointer); }
void operator delete(void* pointer, std::size_t, std::align_val_t) noexcept { std::free(pointer); }
void operator delete[](void* pointer, std::size_t, std::align_val_t) noexcept { std::free(pointer); }
