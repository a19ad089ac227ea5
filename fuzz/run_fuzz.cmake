# cmake -DMODE=build|run -DSOURCE=<frix source> -DDIR=<fuzz build dir> [-DCC= -DCXX=]
#       [-DTARGET=read_problem|problem|options -DSECONDS=N] -P run_fuzz.cmake
# build: configures (once) and builds the clang tree with the fuzz targets.
# run:   runs fuzz_<TARGET> for SECONDS on a scratch corpus seeded from fuzz/corpus/<TARGET>.
cmake_minimum_required(VERSION 3.25)

if(MODE STREQUAL "build")
  if(NOT EXISTS "${DIR}/CMakeCache.txt")
    execute_process(
      COMMAND "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${DIR}"
              "-DCMAKE_C_COMPILER=${CC}" "-DCMAKE_CXX_COMPILER=${CXX}"
              -DCMAKE_BUILD_TYPE=RelWithDebInfo -DFRIX_FUZZ=ON -DFRIX_BUILD_TESTS=OFF -DFRIX_FORTRAN=OFF
      RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
    if(NOT rc EQUAL 0)
      file(REMOVE "${DIR}/CMakeCache.txt")
      message(FATAL_ERROR "configuring the fuzz tree failed:\n${out}")
    endif()
  endif()
  execute_process(
    COMMAND "${CMAKE_COMMAND}" --build "${DIR}" -j2 --target fuzz_read_problem fuzz_problem fuzz_options
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "building the fuzz targets failed:\n${out}")
  endif()
  message(STATUS "fuzz targets built in ${DIR}")
elseif(MODE STREQUAL "run")
  set(corpus "${DIR}/corpus/${TARGET}")
  set(artifacts "${DIR}/artifacts/${TARGET}/")
  file(MAKE_DIRECTORY "${corpus}" "${artifacts}")
  # -rss_limit_mb: a reader must never allocate what the input does not hold.
  # HDF5's own leak on corrupt files (fuzz/hdf5-leaks.supp) is matched by function name,
  # which needs the slow unwinder: libhdf5 is built without frame pointers.
  set(ENV{LSAN_OPTIONS} "suppressions=${SOURCE}/fuzz/hdf5-leaks.supp")
  set(ENV{ASAN_OPTIONS} "fast_unwind_on_malloc=0")
  execute_process(
    COMMAND "${DIR}/fuzz/fuzz_${TARGET}" -max_total_time=${SECONDS} -timeout=20 -rss_limit_mb=2048
            -print_final_stats=1 "-artifact_prefix=${artifacts}" "${corpus}" "${SOURCE}/fuzz/corpus/${TARGET}"
    RESULT_VARIABLE rc OUTPUT_VARIABLE out ERROR_VARIABLE out)
  string(REGEX MATCH "stat::number_of_executed_units: *[0-9]+" execs "${out}")
  string(REGEX MATCH "stat::new_units_added: *[0-9]+" added "${out}")
  if(NOT rc EQUAL 0)
    string(LENGTH "${out}" len)
    if(len GREATER 12000)
      math(EXPR start "${len} - 12000")
      string(SUBSTRING "${out}" ${start} -1 out)
    endif()
    message(FATAL_ERROR "fuzz_${TARGET}: a finding (exit ${rc}); the input is in ${artifacts}\n${out}")
  endif()
  message(STATUS "fuzz_${TARGET}: ${SECONDS} s, ${execs}, ${added}, no finding")
else()
  message(FATAL_ERROR "MODE must be build or run")
endif()
