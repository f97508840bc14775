# Runs one libFuzzer target that the build made (build_fuzzer.cmake); called by ctest (tests/fuzz/CMakeLists.txt).
# A missing binary, a crash, a leak, a sanitizer report or a run that does not finish fails the test.
# Inputs (-D): NAME, BINARY, WORK_DIR, SEED_DIR ("" = none), SECONDS, RUNS (0 = no limit but SECONDS), MAX_LEN.
if(NOT EXISTS "${BINARY}")
  message(FATAL_ERROR "${NAME}: ${BINARY} is not built (the build's fuzz_targets target makes it)")
endif()
file(MAKE_DIRECTORY "${WORK_DIR}")

# A fresh corpus each time, grown from the seeds: a fixed seed then repeats the same mutations. Crash inputs
# are written into WORK_DIR.
set(corpus "${WORK_DIR}/corpus")
file(REMOVE_RECURSE "${corpus}")
file(MAKE_DIRECTORY "${corpus}")
set(corpus_dirs "${corpus}")
if(SEED_DIR)
  if(NOT IS_DIRECTORY "${SEED_DIR}")
    message(FATAL_ERROR "${NAME}: no seed corpus at ${SEED_DIR} (the fuzz_seeds test writes it)")
  endif()
  list(APPEND corpus_dirs "${SEED_DIR}")
endif()
set(limits -max_total_time=${SECONDS})
if(RUNS GREATER 0)
  list(APPEND limits -runs=${RUNS})
endif()
execute_process(
  COMMAND "${BINARY}" ${limits} -seed=1 -max_len=${MAX_LEN} -print_final_stats=1 "-artifact_prefix=${WORK_DIR}/"
          ${corpus_dirs}
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
  message(FATAL_ERROR "${NAME}: the fuzzer stopped with ${run_result} (crash, leak or sanitizer report above)")
endif()
if(run_output MATCHES "runtime error:|ERROR: AddressSanitizer|ERROR: LeakSanitizer|ERROR: libFuzzer")
  message(FATAL_ERROR "${NAME}: sanitizer report in the output")
endif()
if(NOT run_output MATCHES "Done [0-9]+ runs in [0-9]+ second")
  message(FATAL_ERROR "${NAME}: the run did not finish")
endif()
