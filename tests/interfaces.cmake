# Tests of the ways in: public headers as C89/C99/C++, the ABI against its baseline, the
# Fortran module, the examples (C, Fortran, dlopen host), and the installed package used
# from outside the tree. Included by tests/CMakeLists.txt. Tests that need a tool this
# machine lacks are not added (CI installs them all: see README.md).

set(FRIX_TEST_TMP "${CMAKE_CURRENT_BINARY_DIR}/tmp")
set(FRIX_PUBLIC_INCLUDES -I${PROJECT_SOURCE_DIR}/include -I${PROJECT_BINARY_DIR}/include)

# ---- Public headers: C89, C99 and C++98/C++17, pedantic, warnings as errors.
set(FRIX_HEADER_FLAGS -fsyntax-only -Wall -Wextra -pedantic-errors -Werror)
foreach(std c89 c99 c11)
  add_test(NAME public_headers_${std}
           COMMAND ${CMAKE_C_COMPILER} -std=${std} ${FRIX_HEADER_FLAGS} ${FRIX_PUBLIC_INCLUDES}
                   "${CMAKE_CURRENT_SOURCE_DIR}/public_headers.c")
endforeach()
foreach(std c++98 c++17)
  add_test(NAME public_headers_${std}
           COMMAND ${CMAKE_CXX_COMPILER} -x c++ -std=${std} ${FRIX_HEADER_FLAGS} ${FRIX_PUBLIC_INCLUDES}
                   "${CMAKE_CURRENT_SOURCE_DIR}/public_headers.c")
endforeach()

# frix_mpi.h, with MPI's own headers as system headers (they are not ours to check).
if(FRIX_WITH_MPI)
  set(FRIX_MPI_INCLUDES)
  foreach(d ${MPI_C_INCLUDE_DIRS})
    list(APPEND FRIX_MPI_INCLUDES -isystem "${d}")
  endforeach()
  foreach(std c89 c99 c11)
    add_test(NAME public_headers_mpi_${std}
             COMMAND ${CMAKE_C_COMPILER} -std=${std} ${FRIX_HEADER_FLAGS} ${FRIX_PUBLIC_INCLUDES} ${FRIX_MPI_INCLUDES}
                     "${CMAKE_CURRENT_SOURCE_DIR}/public_headers_mpi.c")
  endforeach()
  # frix_mpi_petsc.h with PETSc's headers (C99 and C++17, as PETSc itself asks).
  set(FRIX_PETSC_INCLUDES)
  foreach(d ${PETSC_INCLUDE_DIRS})
    list(APPEND FRIX_PETSC_INCLUDES -isystem "${d}")
  endforeach()
  add_test(NAME public_headers_mpi_petsc_c99
           COMMAND ${CMAKE_C_COMPILER} -std=c99 ${FRIX_HEADER_FLAGS} ${FRIX_PUBLIC_INCLUDES} ${FRIX_MPI_INCLUDES}
                   ${FRIX_PETSC_INCLUDES} -include frix/frix_mpi_petsc.h "${CMAKE_CURRENT_SOURCE_DIR}/public_headers_mpi.c")
  add_test(NAME public_headers_mpi_petsc_c++17
           COMMAND ${CMAKE_CXX_COMPILER} -x c++ -std=c++17 ${FRIX_HEADER_FLAGS} ${FRIX_PUBLIC_INCLUDES}
                   ${FRIX_MPI_INCLUDES} ${FRIX_PETSC_INCLUDES} -include frix/frix_mpi_petsc.h
                   "${CMAKE_CURRENT_SOURCE_DIR}/public_headers_mpi.c")
  foreach(std c++98 c++17)
    add_test(NAME public_headers_mpi_${std}
             COMMAND ${CMAKE_CXX_COMPILER} -x c++ -std=${std} ${FRIX_HEADER_FLAGS} ${FRIX_PUBLIC_INCLUDES}
                     ${FRIX_MPI_INCLUDES} "${CMAKE_CURRENT_SOURCE_DIR}/public_headers_mpi.c")
  endforeach()
endif()

# ---- ABI: abidw (Debian abigail-tools) on libfrix.so against abi/libfrix.so.0.abi.
find_program(FRIX_ABIDW abidw)
find_program(FRIX_ABIDIFF abidiff)
set(FRIX_ABI_BASELINE "${PROJECT_SOURCE_DIR}/abi/libfrix.so.0.abi")
set(FRIX_ABI_HEADERS "${PROJECT_SOURCE_DIR}/include/frix" "${PROJECT_BINARY_DIR}/include/frix")
if(FRIX_ABIDW AND FRIX_ABIDIFF)
  add_test(NAME abi_check
           COMMAND sh "${CMAKE_CURRENT_SOURCE_DIR}/abi_check.sh" $<TARGET_FILE:frix>
                   "${FRIX_ABI_BASELINE}" "${PROJECT_SOURCE_DIR}/abi/frix.suppr"
                   "${FRIX_TEST_TMP}/abi" ${FRIX_ABI_HEADERS})
  # Regenerates the committed baseline from this build: run after an intended ABI change.
  set(FRIX_ABIDW_ARGS)
  foreach(d ${FRIX_ABI_HEADERS})
    list(APPEND FRIX_ABIDW_ARGS --headers-dir "${d}")
  endforeach()
  set(FRIX_ABIDW_OPTIONS ${FRIX_ABIDW_ARGS} --drop-private-types --exported-interfaces-only
      --type-id-style hash --no-corpus-path --no-comp-dir-path --short-locs)
  add_custom_target(abi-baseline
    COMMAND ${FRIX_ABIDW} ${FRIX_ABIDW_OPTIONS} --out-file "${FRIX_ABI_BASELINE}" $<TARGET_FILE:frix>
    DEPENDS frix
    COMMENT "Writing the ABI baseline abi/libfrix.so.0.abi"
    VERBATIM)
  # libfrix_mpi.so against abi/libfrix_mpi.so.0.abi, the same way (the types of frix_mpi.h;
  # MPI's and PETSc's handles are opaque pointers to it); abi-baseline-mpi regenerates it.
  # The baseline is Open MPI's (MPI_Comm is a pointer there, an int in MPICH's ABI).
  if(FRIX_WITH_MPI)
    include(CheckSymbolExists)
    set(CMAKE_REQUIRED_INCLUDES ${MPI_C_INCLUDE_DIRS})
    check_symbol_exists(OPEN_MPI "mpi.h" FRIX_MPI_IS_OPEN_MPI)
    unset(CMAKE_REQUIRED_INCLUDES)
  endif()
  if(FRIX_WITH_MPI AND NOT FRIX_MPI_IS_OPEN_MPI)
    message(STATUS "MPI is not Open MPI: the abi_check_mpi test (an Open MPI baseline) is left out")
  elseif(FRIX_WITH_MPI)
    set(FRIX_ABI_MPI_BASELINE "${PROJECT_SOURCE_DIR}/abi/libfrix_mpi.so.0.abi")
    add_test(NAME abi_check_mpi
             COMMAND sh "${CMAKE_CURRENT_SOURCE_DIR}/abi_check.sh" $<TARGET_FILE:frix_mpi>
                     "${FRIX_ABI_MPI_BASELINE}" "${PROJECT_SOURCE_DIR}/abi/frix.suppr"
                     "${FRIX_TEST_TMP}/abi_mpi" ${FRIX_ABI_HEADERS})
    add_custom_target(abi-baseline-mpi
      COMMAND ${FRIX_ABIDW} ${FRIX_ABIDW_OPTIONS} --out-file "${FRIX_ABI_MPI_BASELINE}" $<TARGET_FILE:frix_mpi>
      DEPENDS frix_mpi
      COMMENT "Writing the ABI baseline abi/libfrix_mpi.so.0.abi"
      VERBATIM)
  endif()
else()
  message(STATUS "abidw/abidiff not found (Debian abigail-tools): the abi_check test is left out")
endif()

# The plugin table against its frozen version-1 layout, and with it every signature.
add_test(NAME abi_plugin_table
         COMMAND ${CMAKE_C_COMPILER} -std=gnu11 -fsyntax-only -Wall -Werror ${FRIX_PUBLIC_INCLUDES}
                 -I${PROJECT_SOURCE_DIR}/abi "${CMAKE_CURRENT_SOURCE_DIR}/abi_table.c")

# ---- Examples (built by examples/CMakeLists.txt into the build's examples/ folder).
set(FRIX_EXAMPLES_DIR "${PROJECT_BINARY_DIR}/examples")
add_test(NAME example_c_solve_csc COMMAND "${FRIX_EXAMPLES_DIR}/solve_csc")
add_test(NAME example_c_fclib_two_solvers
         COMMAND sh -c "\"$1/make_example\" \"$2/ex.hdf5\" && \"$1/fclib_two_solvers\" \"$2/ex.hdf5\" \"$2/ex_solved.hdf5\""
                 sh "${FRIX_EXAMPLES_DIR}" "${FRIX_TEST_TMP}")
# The host finds libfrix.so.0 by name through the loader's path, and is not linked to it.
# LeakSanitizer cannot scan the globals of libraries that dlclose has unmapped (libfrix's
# dependencies keep small allocations there), so leak detection is off for the host alone.
add_test(NAME example_plugin_host
         COMMAND sh -c "readelf -d \"$1/plugin_host\" | grep -q 'NEEDED.*libfrix' && { echo 'plugin_host is linked to libfrix'; exit 1; }; LD_LIBRARY_PATH=\"$2\" \"$1/plugin_host\""
                 sh "${FRIX_EXAMPLES_DIR}" $<TARGET_FILE_DIR:frix>)
set_tests_properties(example_plugin_host PROPERTIES ENVIRONMENT "ASAN_OPTIONS=detect_leaks=0")

# README.md shows examples/c/solve_csc.c in full: the copy must not drift from the file.
add_test(NAME readme_shows_solve_csc
         COMMAND sh -c "sed -n '/^`examples\\/c\\/solve_csc.c`, in full:$/,/^```$/p' \"$1/README.md\" | sed '1,3d;$d' | diff - \"$1/examples/c/solve_csc.c\""
                 sh "${PROJECT_SOURCE_DIR}")

# ---- Fortran: the module against the C headers (text only, no compiler needed), the
# module's own test and the example.
add_test(NAME fortran_binding_complete
         COMMAND ${CMAKE_COMMAND} -DFRIX_INCLUDE_DIR=${PROJECT_SOURCE_DIR}/include/frix
                 -P "${CMAKE_CURRENT_SOURCE_DIR}/fortran_binding_complete.cmake")
if(TARGET frix_fortran)
  add_executable(test_fortran test_fortran.f90)
  target_link_libraries(test_fortran PRIVATE frix_fortran)
  # Exact real comparisons are meant; and the getters called inside .and. have no side
  # effects, so whether gfortran evaluates them there does not matter.
  target_compile_options(test_fortran PRIVATE -std=f2008 -Wall -Wextra -Wno-compare-reals
                         -Wno-function-elimination)
  add_test(NAME test_fortran COMMAND test_fortran WORKING_DIRECTORY "${FRIX_TEST_TMP}")
  add_test(NAME example_fortran COMMAND "${FRIX_EXAMPLES_DIR}/fortran_solve_local")
endif()

# ---- The installed package, used from outside the tree both ways (CMake package and
# pkg-config): cmake --install into a scratch prefix, configure examples/ against it, run.
set(FRIX_INSTALL_TEST_FLAGS "")
if(FRIX_SANITIZE)
  set(FRIX_INSTALL_TEST_FLAGS "-fsanitize=address,undefined -fno-omit-frame-pointer")
endif()
add_test(NAME install_and_use
         COMMAND sh "${CMAKE_CURRENT_SOURCE_DIR}/install_and_use.sh" "${PROJECT_BINARY_DIR}"
                 "${PROJECT_SOURCE_DIR}" "${FRIX_TEST_TMP}/install" "${FRIX_INSTALL_TEST_FLAGS}")
set_tests_properties(install_and_use PROPERTIES TIMEOUT 600)
