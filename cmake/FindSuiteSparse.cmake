# Finds UMFPACK and CHOLMOD of Debian's SuiteSparse (5.x ships no CMake config for them).
# Defines SuiteSparse::UMFPACK, SuiteSparse::CHOLMOD and SuiteSparse_FOUND.
find_path(SuiteSparse_INCLUDE_DIR NAMES umfpack.h cholmod.h PATH_SUFFIXES suitesparse)
find_library(SuiteSparse_UMFPACK_LIBRARY NAMES umfpack)
find_library(SuiteSparse_CHOLMOD_LIBRARY NAMES cholmod)
find_library(SuiteSparse_CONFIG_LIBRARY NAMES suitesparseconfig)

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(SuiteSparse REQUIRED_VARS
  SuiteSparse_INCLUDE_DIR SuiteSparse_UMFPACK_LIBRARY SuiteSparse_CHOLMOD_LIBRARY
  SuiteSparse_CONFIG_LIBRARY)

if(SuiteSparse_FOUND)
  foreach(comp UMFPACK CHOLMOD)
    if(NOT TARGET SuiteSparse::${comp})
      add_library(SuiteSparse::${comp} UNKNOWN IMPORTED)
      set_target_properties(SuiteSparse::${comp} PROPERTIES
        IMPORTED_LOCATION "${SuiteSparse_${comp}_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${SuiteSparse_INCLUDE_DIR}"
        INTERFACE_LINK_LIBRARIES "${SuiteSparse_CONFIG_LIBRARY}")
    endif()
  endforeach()
endif()
mark_as_advanced(SuiteSparse_INCLUDE_DIR SuiteSparse_UMFPACK_LIBRARY SuiteSparse_CHOLMOD_LIBRARY
                 SuiteSparse_CONFIG_LIBRARY)
