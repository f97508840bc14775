#include "vifusion/dds/entity.hpp"

#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::dds {

Entity& Entity::operator=(Entity&& other) noexcept {
  if (this != &other) {
    reset();
    handle_ = other.handle_;
    other.handle_ = 0;
  }
  return *this;
}

void Entity::reset() {
  // A parent deleted first has already deleted this entity; Cyclone then answers
  // ALREADY_DELETED / BAD_PARAMETER, which is harmless here.
  if (handle_ > 0) static_cast<void>(dds_delete(handle_));
  handle_ = 0;
}

dds_entity_t checkEntity(dds_entity_t rc, std::string_view what) {
  checkReturn(rc, what);
  return rc;
}

void checkReturn(dds_return_t rc, std::string_view what) {
  if (rc < 0) throw Error(std::string(what) + ": " + dds_strretcode(rc));
}

}  // namespace vifusion::dds
