# Builds one libFuzzer target with clang++ as a build step (tests/fuzz/CMakeLists.txt): each source compiled to
# its own object with its header dependencies, then one link; the dependencies of all objects go into DEPFILE as
# the binary's, so the build system rebuilds the target when a source or any header it includes changes.
# Inputs (-D): CLANGXX, BINARY, DEPFILE, TARGET_SOURCE, SOURCES, INCLUDE_DIRS, LINK_FILES and FLAGS
# ('|'-separated).
string(REPLACE "|" ";" sources "${SOURCES}")
string(REPLACE "|" ";" include_dirs "${INCLUDE_DIRS}")
string(REPLACE "|" ";" link_files "${LINK_FILES}")
string(REPLACE "|" ";" flags "${FLAGS}")
list(REMOVE_DUPLICATES include_dirs)
list(TRANSFORM include_dirs PREPEND "-I")
get_filename_component(name "${BINARY}" NAME)
set(object_dir "${BINARY}.objects")
file(REMOVE_RECURSE "${object_dir}")
file(MAKE_DIRECTORY "${object_dir}")

set(objects "")
set(dependencies "")
set(index 0)
foreach(source IN LISTS TARGET_SOURCE sources)
  get_filename_component(stem "${source}" NAME_WE)
  # The index keeps sources of the same name from different folders apart.
  set(object "${object_dir}/${index}_${stem}.o")
  execute_process(
    COMMAND "${CLANGXX}" ${flags} ${include_dirs} -MD -MF "${object}.d" -c "${source}" -o "${object}"
    RESULT_VARIABLE compile_result)
  if(NOT compile_result EQUAL 0)
    message(FATAL_ERROR "${name}: ${CLANGXX} could not compile ${source} (${compile_result})")
  endif()
  # "object: a.cpp b.hpp \<newline> c.hpp …" → the prerequisites alone.
  file(READ "${object}.d" rule)
  string(REPLACE "\\\n" " " rule "${rule}")
  string(REGEX REPLACE "^[^:]*: *" "" rule "${rule}")
  string(STRIP "${rule}" rule)
  string(APPEND dependencies " ${rule}")
  list(APPEND objects "${object}")
  math(EXPR index "${index} + 1")
endforeach()

execute_process(COMMAND "${CLANGXX}" ${flags} ${objects} ${link_files} -o "${BINARY}" RESULT_VARIABLE link_result)
if(NOT link_result EQUAL 0)
  message(FATAL_ERROR "${name}: ${CLANGXX} could not link ${BINARY} (${link_result})")
endif()
file(WRITE "${DEPFILE}" "${BINARY}:${dependencies}\n")
