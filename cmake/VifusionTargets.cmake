# Helpers that give every vifusion library the same shape (OKVIS2 style):
# one static library per folder, headers under include/vifusion/<name>/, a namespaced alias.

# Warnings are errors on our own code only; third-party headers come in as SYSTEM.
set(VIFUSION_WARNING_FLAGS -Wall -Wextra -Wpedantic -Werror -Wno-psabi)

# vifusion_library(<name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates vifusion_<name> with alias vifusion::<name>.
function(vifusion_library name)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target vifusion_${name})
  if(ARG_SOURCES)
    add_library(${target} STATIC ${ARG_SOURCES})
    set(scope PUBLIC)
    target_compile_options(${target} PRIVATE ${VIFUSION_WARNING_FLAGS})
  else()
    add_library(${target} INTERFACE)
    set(scope INTERFACE)
  endif()
  add_library(vifusion::${name} ALIAS ${target})
  target_include_directories(${target} ${scope}
    $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include>)
  target_compile_features(${target} ${scope} cxx_std_20)
  if(ARG_PUBLIC_DEPS)
    target_link_libraries(${target} ${scope} ${ARG_PUBLIC_DEPS})
  endif()
  if(ARG_PRIVATE_DEPS)
    target_link_libraries(${target} PRIVATE ${ARG_PRIVATE_DEPS})
  endif()
endfunction()

# vifusion_executable(<name> SOURCES ... DEPS ...)
function(vifusion_executable name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_compile_options(${name} PRIVATE ${VIFUSION_WARNING_FLAGS})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
endfunction()
