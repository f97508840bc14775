#pragma once
// Surfels of random 32-bit words (NaN payloads, infinities and denormals included) and their bitwise
// comparison: what the map's transfers (export, import) must carry bit for bit.

#include <cstdint>
#include <cstring>
#include <random>
#include <span>
#include <vector>

#include "vifusion/map/surfel.hpp"

namespace vifusion::test {

inline std::vector<map::Surfel> randomSurfels(std::size_t count, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::vector<map::Surfel> surfels(count);
  for (map::Surfel& s : surfels) {
    std::uint32_t words[sizeof(map::Surfel) / sizeof(std::uint32_t)];
    for (std::uint32_t& word : words) word = random();
    std::memcpy(static_cast<void*>(&s), words, sizeof(words));
  }
  return surfels;
}

inline bool sameBits(std::span<const map::Surfel> a, std::span<const map::Surfel> b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size_bytes()) == 0);
}

}  // namespace vifusion::test
