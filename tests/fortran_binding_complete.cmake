# The Fortran module (include/frix/frix.f90) against the C headers, as text: every
# enumerator of the public headers must be a parameter of the module with the same value,
# and every exported function must be bound, under the names the module's header comment
# gives for the few that Fortran's case-insensitivity forces to rename. Run as
#   cmake -DFRIX_INCLUDE_DIR=include/frix -P tests/fortran_binding_complete.cmake
# (no Fortran compiler needed: it keeps the module from falling behind the C API).

if(NOT FRIX_INCLUDE_DIR)
  message(FATAL_ERROR "pass -DFRIX_INCLUDE_DIR=<the include/frix folder>")
endif()

# C names renamed in Fortran (C name -> Fortran name), and C functions not bound on purpose.
set(renamed
  FRIX_PROBLEM_LOCAL=FRIX_PROBLEM_KIND_LOCAL FRIX_PROBLEM_GLOBAL=FRIX_PROBLEM_KIND_GLOBAL
  FRIX_PROBLEM_ROLLING_LOCAL=FRIX_PROBLEM_KIND_ROLLING_LOCAL
  FRIX_PROBLEM_ROLLING_GLOBAL=FRIX_PROBLEM_KIND_ROLLING_GLOBAL
  FRIX_INFO_STATUS=FRIX_INFO_KEY_STATUS FRIX_INFO_ITERATIONS=FRIX_INFO_KEY_ITERATIONS
  FRIX_INFO_ERROR=FRIX_INFO_KEY_ERROR)
set(unbound frix_plugin_api)  # the function table for C hosts that dlopen the library

# frix_mpi.h and frix_mpi_petsc.h are libfrix_mpi's headers, which the module does not bind
# (it is libfrix's).
file(GLOB headers "${FRIX_INCLUDE_DIR}/*.h")
list(FILTER headers EXCLUDE REGEX "/frix_mpi(_petsc)?\\.h$")
set(c_text "")
foreach(h ${headers})
  file(READ "${h}" t)
  string(APPEND c_text "${t}\n")
endforeach()
file(READ "${FRIX_INCLUDE_DIR}/frix.f90" f_text)
string(TOUPPER "${f_text}" f_upper)

set(problems "")
set(checked_constants 0)
string(REGEX MATCHALL "FRIX_[A-Z0-9_]+ *= *-?[0-9]+" c_constants "${c_text}")
foreach(pair ${c_constants})
  string(REGEX REPLACE " *= *" ";" nv "${pair}")
  list(GET nv 0 name)
  list(GET nv 1 value)
  set(f_name "${name}")
  foreach(r ${renamed})
    if(r MATCHES "^${name}=(.*)$")
      set(f_name "${CMAKE_MATCH_1}")
    endif()
  endforeach()
  # The parameter, whole name, anywhere in the module (case-insensitive, as Fortran).
  if(NOT f_upper MATCHES "[^A-Z0-9_]${f_name} *= *(-?[0-9]+)")
    list(APPEND problems "constant ${name} (${value}) is missing as ${f_name}")
  elseif(NOT CMAKE_MATCH_1 STREQUAL value)
    list(APPEND problems "constant ${f_name} is ${CMAKE_MATCH_1} in Fortran, ${value} in C")
  endif()
  math(EXPR checked_constants "${checked_constants} + 1")
endforeach()

# Exported functions: FRIX_API <return type> <name>(.
set(checked_functions 0)
string(REGEX MATCHALL "FRIX_API[^;(]*[ *]frix_[A-Za-z0-9_]+ *\\(" c_functions "${c_text}")
foreach(decl ${c_functions})
  string(REGEX REPLACE ".*[ *](frix_[A-Za-z0-9_]+) *\\($" "\\1" name "${decl}")
  list(FIND unbound "${name}" skip)
  if(skip GREATER -1)
    continue()
  endif()
  if(NOT f_text MATCHES "bind\\(C, *name='${name}'\\)")
    list(APPEND problems "function ${name} is not bound")
  endif()
  math(EXPR checked_functions "${checked_functions} + 1")
endforeach()

if(checked_constants LESS 50 OR checked_functions LESS 50)
  message(FATAL_ERROR "only ${checked_constants} constants and ${checked_functions} functions "
                      "found in ${FRIX_INCLUDE_DIR}: the patterns no longer match the headers")
endif()
if(problems)
  list(JOIN problems "\n  " text)
  message(FATAL_ERROR "frix.f90 is behind the C headers:\n  ${text}")
endif()
message(STATUS "frix.f90: ${checked_constants} constants and ${checked_functions} functions "
               "match the C headers")
