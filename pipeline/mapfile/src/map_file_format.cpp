#include "vifusion/mapfile/map_file_format.hpp"

#include <algorithm>

namespace vifusion::mapfile {
namespace {

constexpr std::array<std::string_view, kSectionCount> kNames = {"meta",     "calib",   "state", "traj",
                                                                "keyframe", "surfels", "end"};
static_assert(std::all_of(kNames.begin(), kNames.end(),
                          [](std::string_view name) { return name.size() <= kSectionTagBytes; }));

}  // namespace

std::string_view sectionName(MapSection section) { return kNames[static_cast<std::size_t>(section)]; }

std::optional<MapSection> sectionFromTag(const std::array<char, kSectionTagBytes>& tag) {
  const auto end = std::find(tag.begin(), tag.end(), '\0');
  const std::string_view name(tag.data(), static_cast<std::size_t>(end - tag.begin()));
  if (std::any_of(end, tag.end(), [](char c) { return c != '\0'; })) return std::nullopt;
  for (int i = 0; i < kSectionCount; ++i)
    if (kNames[static_cast<std::size_t>(i)] == name) return static_cast<MapSection>(i);
  return std::nullopt;
}

}  // namespace vifusion::mapfile
