#pragma once
// Ownership of Cyclone DDS entities (RAII): an Entity deletes its handle, and with it every child
// entity Cyclone created under it, when it goes out of scope.

#include <dds/dds.h>

#include <string_view>

namespace vifusion::dds {

class Entity {
 public:
  Entity() = default;
  /// Takes ownership of `handle`, which must be a valid (positive) entity handle.
  explicit Entity(dds_entity_t handle) : handle_(handle) {}
  Entity(Entity&& other) noexcept : handle_(other.handle_) { other.handle_ = 0; }
  Entity& operator=(Entity&& other) noexcept;
  Entity(const Entity&) = delete;
  Entity& operator=(const Entity&) = delete;
  ~Entity() { reset(); }

  dds_entity_t get() const { return handle_; }
  /// Deletes the entity now; a later get() returns 0.
  void reset();

 private:
  dds_entity_t handle_ = 0;
};

/// Returns `rc` when it is a valid entity handle; otherwise throws vifusion::Error
/// "<what>: <Cyclone's text for rc>".
dds_entity_t checkEntity(dds_entity_t rc, std::string_view what);
/// Throws vifusion::Error "<what>: <Cyclone's text for rc>" unless rc is DDS_RETCODE_OK (or positive).
void checkReturn(dds_return_t rc, std::string_view what);

}  // namespace vifusion::dds
