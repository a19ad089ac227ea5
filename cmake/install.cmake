# cmake --install: headers (with the Fortran module source), libfrix.so.0 and libfrix.a
# (and libfrix_mpi.so.0 with frix-mpi, when built), the
# Fortran module and its library, the frix CLI (tools/CMakeLists.txt), a CMake package
# (find_package(frix) -> frix::frix, frix::frix_static, frix::fortran; COMPONENTS frix_mpi ->
# frix::frix_mpi) and frix.pc.
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
  # An export set of its own, loaded only for the frix_mpi component: frix::frix_mpi names
  # MPI::MPI_C, which a project without MPI cannot resolve.
  install(TARGETS frix_mpi EXPORT frixMpiTargets LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
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
if(TARGET frix_mpi)
  install(EXPORT frixMpiTargets NAMESPACE frix:: DESTINATION ${FRIX_CMAKE_DIR} FILE frix_mpi-targets.cmake)
endif()
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
# The HDF5 named is the one libfrix links: the pkg-config module whose -L is that library's
# folder, else the folder itself. Debian's plain `hdf5` module is the MPI build (it pulls
# libmpi); libfrix links the serial one (`hdf5-serial`).
set(FRIX_PC_REQUIRES_PRIVATE "")
set(FRIX_PC_HDF5_LIBS "")
set(frix_hdf5_lib "")
foreach(lib IN LISTS HDF5_C_LIBRARIES HDF5_LIBRARIES)
  if(NOT frix_hdf5_lib AND lib MATCHES "/libhdf5(_serial)?\\.(so|a)$")
    set(frix_hdf5_lib "${lib}")
  endif()
endforeach()
if(frix_hdf5_lib)
  get_filename_component(frix_hdf5_dir "${frix_hdf5_lib}" DIRECTORY)
  find_package(PkgConfig QUIET)
  if(PKG_CONFIG_EXECUTABLE)
    foreach(module hdf5-serial hdf5)
      execute_process(COMMAND "${PKG_CONFIG_EXECUTABLE}" --libs-only-L ${module}
                      OUTPUT_VARIABLE frix_hdf5_L RESULT_VARIABLE frix_pc_rc ERROR_QUIET
                      OUTPUT_STRIP_TRAILING_WHITESPACE)
      separate_arguments(frix_hdf5_L UNIX_COMMAND "${frix_hdf5_L}")
      if(NOT FRIX_PC_REQUIRES_PRIVATE AND frix_pc_rc EQUAL 0 AND "-L${frix_hdf5_dir}" IN_LIST frix_hdf5_L)
        set(FRIX_PC_REQUIRES_PRIVATE "Requires.private: ${module}")
      endif()
    endforeach()
  endif()
  if(NOT FRIX_PC_REQUIRES_PRIVATE)
    get_filename_component(frix_hdf5_name "${frix_hdf5_lib}" NAME_WE)
    string(REGEX REPLACE "^lib" "" frix_hdf5_name "${frix_hdf5_name}")
    set(FRIX_PC_HDF5_LIBS "-L${frix_hdf5_dir} -l${frix_hdf5_name} ")
  endif()
else()
  set(FRIX_PC_REQUIRES_PRIVATE "Requires.private: hdf5")
endif()
configure_file(cmake/frix.pc.in "${CMAKE_CURRENT_BINARY_DIR}/frix.pc" @ONLY)
install(FILES "${CMAKE_CURRENT_BINARY_DIR}/frix.pc" DESTINATION ${CMAKE_INSTALL_LIBDIR}/pkgconfig)
