#include <gtest/gtest.h>
#include <sys/mman.h>
#include <unistd.h>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "vifusion/core/resident_memory.hpp"

namespace vifusion {
namespace {

using Matrix12d = Eigen::Matrix<double, 12, 12>;

// 64 MiB: above glibc's largest dynamic mmap threshold (32 MiB on 64-bit), so every buffer here is a
// fresh mapping whose pages nothing has written yet, whatever the tests before it freed.
constexpr std::size_t kBufferBytes = std::size_t{64} << 20;
constexpr std::size_t kElements = kBufferBytes / sizeof(Matrix12d);

/// Share of the pages spanned by [data, data + bytes) that are resident (mincore(2)).
double residentFraction(const void* data, std::size_t bytes) {
  const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const std::uintptr_t begin = reinterpret_cast<std::uintptr_t>(data) & ~(page - 1);
  const std::uintptr_t end = reinterpret_cast<std::uintptr_t>(data) + bytes;
  std::vector<unsigned char> pages((end - begin + page - 1) / page);
  if (mincore(reinterpret_cast<void*>(begin), end - begin, pages.data()) != 0) return -1.0;
  std::size_t resident = 0;
  for (const unsigned char state : pages) resident += state & 1u;
  return static_cast<double>(resident) / static_cast<double>(pages.size());
}

// The controls: what the helpers exist to avoid. If these ever fail, the allocator or the kernel now
// maps pages eagerly and the helpers cost only a start-up write.
TEST(ResidentMemory, PlainReserveAndEigenResizeLeavePagesUnmapped) {
  std::vector<Matrix12d> reserved;
  reserved.reserve(kElements);
  EXPECT_LT(residentFraction(reserved.data(), kBufferBytes), 0.01);
  std::vector<Matrix12d> resized;
  resized.resize(kElements);  // Eigen's default constructor writes nothing
  EXPECT_LT(residentFraction(resized.data(), kBufferBytes), 0.01);
}

TEST(ResidentMemory, ReserveResidentMapsEveryPageAndLeavesTheVectorEmpty) {
  std::vector<Matrix12d> values;
  reserveResident(values, kElements, Matrix12d::Zero().eval());
  EXPECT_TRUE(values.empty());
  const std::size_t capacity = values.capacity();
  ASSERT_GE(capacity, kElements);
  EXPECT_EQ(residentFraction(values.data(), kElements * sizeof(Matrix12d)), 1.0);
  const Matrix12d* storage = values.data();
  values.push_back(Matrix12d::Identity());  // within the capacity: no reallocation
  EXPECT_EQ(values.data(), storage);
}

TEST(ResidentMemory, ResizeResidentFillsAndMapsEveryPage) {
  std::vector<Matrix12d> values;
  resizeResident(values, kElements, Matrix12d::Constant(2.0).eval());
  ASSERT_EQ(values.size(), kElements);
  EXPECT_EQ(values.back()(11, 11), 2.0);
  EXPECT_EQ(residentFraction(values.data(), kElements * sizeof(Matrix12d)), 1.0);
}

}  // namespace
}  // namespace vifusion
