#include "vifusion/dds/topics.hpp"

#include "vifusion/core/error.hpp"

namespace vifusion::dds {

std::string ddsTopicName(std::string_view name) {
  const std::string_view given = name;
  if (name.starts_with("rt/")) {
    name.remove_prefix(3);
  } else if (name.starts_with('/')) {
    name.remove_prefix(1);
  }
  if (name.empty() || name.starts_with('/')) {
    throw Error("DDS topic name '" + std::string(given) + "' names no topic");
  }
  return "rt/" + std::string(name);
}

}  // namespace vifusion::dds
