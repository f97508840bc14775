# Compiles one libFuzzer target with clang++ and runs it; called by ctest (tests/fuzz/CMakeLists.txt).
# A compile error, a crash, a sanitizer report or fewer executions than asked fail the test.
# Inputs (-D): CLANGXX, NAME, TARGET_SOURCE, SOURCES and INCLUDE_DIRS ('|'-separated), FLAGS ('|'-separated),
# WORK_DIR, RUNS, MAX_LEN.
string(REPLACE "|" ";" sources "${SOURCES}")
string(REPLACE "|" ";" include_dirs "${INCLUDE_DIRS}")
string(REPLACE "|" ";" flags "${FLAGS}")
list(TRANSFORM include_dirs PREPEND "-I")
file(MAKE_DIRECTORY "${WORK_DIR}")
set(binary "${WORK_DIR}/${NAME}")

execute_process(
  COMMAND "${CLANGXX}" ${flags} ${include_dirs} "${TARGET_SOURCE}" ${sources} -o "${binary}"
  RESULT_VARIABLE compile_result)
if(NOT compile_result EQUAL 0)
  message(FATAL_ERROR "${NAME}: ${CLANGXX} failed (${compile_result})")
endif()

# A fixed seed makes a run repeatable; crash inputs are written into WORK_DIR.
execute_process(
  COMMAND "${binary}" -runs=${RUNS} -seed=1 -max_len=${MAX_LEN} -print_final_stats=1 "-artifact_prefix=${WORK_DIR}/"
  WORKING_DIRECTORY "${WORK_DIR}"
  RESULT_VARIABLE run_result
  OUTPUT_VARIABLE run_output
  ERROR_VARIABLE run_output)
string(LENGTH "${run_output}" output_length)
if(output_length GREATER 4000)
  math(EXPR tail_start "${output_length} - 4000")
  string(SUBSTRING "${run_output}" ${tail_start} -1 run_output_tail)
else()
  set(run_output_tail "${run_output}")
endif()
message("${run_output_tail}")
if(NOT run_result EQUAL 0)
  message(FATAL_ERROR "${NAME}: the fuzzer stopped with ${run_result} (crash or sanitizer report above)")
endif()
if(run_output MATCHES "runtime error:|ERROR: AddressSanitizer|ERROR: libFuzzer")
  message(FATAL_ERROR "${NAME}: sanitizer report in the output")
endif()
if(NOT run_output MATCHES "Done ${RUNS} runs")
  message(FATAL_ERROR "${NAME}: did not complete ${RUNS} executions")
endif()
