# cmake --install: headers (with the Fortran module source), libfrix.so.0 and libfrix.a
# (and libfrix_mpi.so.0 with frix-mpi, when built), the
# Fortran module and its library, the frix CLI (tools/CMakeLists.txt), a CMake package
# (find_package(frix) -> frix::frix, frix::frix_static, frix::fortran) and frix.pc.
include(CMakePackageConfigHelpers)

# The installed CLI finds the installed libfrix.so.0 relative to itself, wherever the prefix.
file(RELATIVE_PATH FRIX_BIN_TO_LIB "/${CMAKE_INSTALL_BINDIR}" "/${CMAKE_INSTALL_LIBDIR}")
set_target_properties(frix_cli PROPERTIES INSTALL_RPATH "$ORIGIN/${FRIX_BIN_TO_LIB}")
if(TARGET frix_mpi_cli)
  set_target_properties(frix_mpi_cli PROPERTIES INSTALL_RPATH "$ORIGIN/${FRIX_BIN_TO_LIB}")
endif()

install(TARGETS frix frix_static EXPORT frixTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
if(TARGET frix_mpi)
  install(TARGETS frix_mpi EXPORT frixTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(DIRECTORY include/frix DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
else()
  install(DIRECTORY include/frix DESTINATION ${CMAKE_INSTALL_INCLUDEDIR} PATTERN frix_mpi.h EXCLUDE
          PATTERN frix_mpi_petsc.h EXCLUDE)
endif()
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/include/frix/frix_version.h"
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/frix)
if(TARGET frix_fortran)
  install(TARGETS frix_fortran EXPORT frixTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
  install(FILES "${CMAKE_CURRENT_BINARY_DIR}/fortran/frix.mod"
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/frix)
endif()

set(FRIX_CMAKE_DIR "${CMAKE_INSTALL_LIBDIR}/cmake/frix")
install(EXPORT frixTargets NAMESPACE frix:: DESTINATION ${FRIX_CMAKE_DIR})
configure_package_config_file(cmake/frix-config.cmake.in
  "${CMAKE_CURRENT_BINARY_DIR}/frix-config.cmake" INSTALL_DESTINATION ${FRIX_CMAKE_DIR})
# 0.x: a new minor version may break, so only the same minor is compatible until 1.0.
write_basic_package_version_file("${CMAKE_CURRENT_BINARY_DIR}/frix-config-version.cmake"
  COMPATIBILITY SameMinorVersion)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/frix-config.cmake"
              "${CMAKE_CURRENT_BINARY_DIR}/frix-config-version.cmake"
              cmake/FindSuiteSparse.cmake
        DESTINATION ${FRIX_CMAKE_DIR})

# pkg-config: the static dependencies go to Requires.private (hdf5 ships a .pc) and
# Libs.private (SuiteSparse 5 and OpenBLAS on Debian 12 do not all ship one).
# Relocatable: the prefix is found from the .pc file's own place.
file(RELATIVE_PATH FRIX_PC_TO_PREFIX "/${CMAKE_INSTALL_LIBDIR}/pkgconfig" "/")
configure_file(cmake/frix.pc.in "${CMAKE_CURRENT_BINARY_DIR}/frix.pc" @ONLY)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/frix.pc" DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
