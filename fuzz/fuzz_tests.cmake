# Short libFuzzer runs in the test suite (included by tests/CMakeLists.txt).
# libFuzzer needs clang, and coverage instrumentation of the code under test, so the fixture
# test fuzz_build configures and builds a clang tree of the library and the fuzz targets
# (-DFRIX_FUZZ=ON) in <build>/fuzz-build; then fuzz_<target> runs each target for
# FRIX_FUZZ_SECONDS on its committed seed corpus (fuzz/corpus/<name>, read only: new inputs
# go to <build>/fuzz-build/corpus). A finding (crash, leak, abort, timeout) fails the test
# and leaves the input in <build>/fuzz-build/artifacts. Registered only when a clang that
# links -fsanitize=fuzzer is found, and not in sanitizer builds (the fuzz tree has its own).
option(FRIX_FUZZ_TESTS "Run short libFuzzer runs in the test suite (needs clang with libFuzzer)" ON)
set(FRIX_FUZZ_SECONDS 20 CACHE STRING "Seconds of each fuzz target's run in the test suite")

if(FRIX_FUZZ_TESTS AND NOT FRIX_SANITIZE AND NOT FRIX_TSAN)
  find_program(FRIX_CLANG NAMES clang clang-14 clang-15 clang-16)
  find_program(FRIX_CLANGXX NAMES clang++ clang++-14 clang++-15 clang++-16)
  set(FRIX_HAVE_LIBFUZZER OFF)
  if(FRIX_CLANG AND FRIX_CLANGXX)
    set(probe_dir "${CMAKE_CURRENT_BINARY_DIR}/fuzz_probe")
    file(MAKE_DIRECTORY "${probe_dir}")
    file(WRITE "${probe_dir}/probe.c"
         "#include <stddef.h>\n#include <stdint.h>\n"
         "int LLVMFuzzerTestOneInput(const uint8_t *d, size_t n) { (void)d; (void)n; return 0; }\n")
    execute_process(COMMAND "${FRIX_CLANG}" -fsanitize=fuzzer,address,undefined probe.c -o probe
                    WORKING_DIRECTORY "${probe_dir}" RESULT_VARIABLE probe_rc OUTPUT_QUIET ERROR_QUIET)
    if(probe_rc EQUAL 0)
      set(FRIX_HAVE_LIBFUZZER ON)
    endif()
  endif()
  if(FRIX_HAVE_LIBFUZZER)
    set(fuzz_dir "${CMAKE_BINARY_DIR}/fuzz-build")
    add_test(NAME fuzz_build
             COMMAND "${CMAKE_COMMAND}" -DMODE=build "-DSOURCE=${PROJECT_SOURCE_DIR}" "-DDIR=${fuzz_dir}"
                     "-DCC=${FRIX_CLANG}" "-DCXX=${FRIX_CLANGXX}"
                     -P "${PROJECT_SOURCE_DIR}/fuzz/run_fuzz.cmake")
    set_tests_properties(fuzz_build PROPERTIES FIXTURES_SETUP frix_fuzz TIMEOUT 1200)
    foreach(target read_problem problem options)
      add_test(NAME fuzz_${target}
               COMMAND "${CMAKE_COMMAND}" -DMODE=run "-DSOURCE=${PROJECT_SOURCE_DIR}" "-DDIR=${fuzz_dir}"
                       -DTARGET=${target} -DSECONDS=${FRIX_FUZZ_SECONDS}
                       -P "${PROJECT_SOURCE_DIR}/fuzz/run_fuzz.cmake")
      math(EXPR fuzz_timeout "${FRIX_FUZZ_SECONDS} * 3 + 120")
      set_tests_properties(fuzz_${target} PROPERTIES FIXTURES_REQUIRED frix_fuzz TIMEOUT ${fuzz_timeout})
    endforeach()
  else()
    message(STATUS "frix: no clang with libFuzzer found: the fuzz_* tests are not registered")
  endif()
endif()
