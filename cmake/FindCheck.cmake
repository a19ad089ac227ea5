# Finds the Check unit-test framework (Debian package `check`, which ships check.pc).
# Defines Check::Check and Check_FOUND.
find_package(PkgConfig QUIET)
if(PkgConfig_FOUND)
  pkg_check_modules(PC_CHECK QUIET check)
endif()
find_path(Check_INCLUDE_DIR NAMES check.h HINTS ${PC_CHECK_INCLUDE_DIRS})
find_library(Check_LIBRARY NAMES check_pic check HINTS ${PC_CHECK_LIBRARY_DIRS})

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(Check REQUIRED_VARS Check_INCLUDE_DIR Check_LIBRARY)

if(Check_FOUND AND NOT TARGET Check::Check)
  add_library(Check::Check INTERFACE IMPORTED)
  # Debian's libcheck needs subunit, rt, m and pthread, listed by check.pc.
  set(_check_libs "${Check_LIBRARY}")
  foreach(lib ${PC_CHECK_LIBRARIES})
    if(NOT lib MATCHES "^check(_pic)?$")
      list(APPEND _check_libs ${lib})
    endif()
  endforeach()
  set_target_properties(Check::Check PROPERTIES
    INTERFACE_INCLUDE_DIRECTORIES "${Check_INCLUDE_DIR}"
    INTERFACE_LINK_LIBRARIES "${_check_libs}")
endif()
mark_as_advanced(Check_INCLUDE_DIR Check_LIBRARY)
