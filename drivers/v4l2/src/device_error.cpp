#include "vifusion/v4l2/device_error.hpp"

#include <cerrno>
#include <cstring>

namespace vifusion::v4l2 {

bool isDeviceGoneErrno(int error_number) {
  return error_number == ENODEV || error_number == ENXIO || error_number == EIO;
}

const char* errnoName(int error_number) {
  const char* name = ::strerrorname_np(error_number);
  return name != nullptr ? name : "unknown errno";
}

std::string errnoText(int error_number) {
  // strerrorname_np/strerrordesc_np (glibc ≥ 2.32) are thread-safe, unlike strerror.
  const char* name = ::strerrorname_np(error_number);
  const char* description = ::strerrordesc_np(error_number);
  std::string text = name != nullptr ? name : "errno " + std::to_string(error_number);
  if (description != nullptr) text += std::string(" (") + description + ")";
  return text;
}

}  // namespace vifusion::v4l2
