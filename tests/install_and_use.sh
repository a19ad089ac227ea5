#!/bin/sh
# cmake --install into a scratch prefix, then build examples/ out of tree against the
# installed copy, once through find_package(frix) and once through pkg-config, and run the
# C example, the dlopen host and (when built) the Fortran example from each.
#   install_and_use.sh BUILD_DIR SOURCE_DIR WORK_DIR EXTRA_C_FLAGS
set -eu
build=$1 src=$2 work=$3 flags=$4
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"
for f in include/frix/frix.h include/frix/frix_version.h include/frix/frix_plugin.h bin/frix \
         lib/libfrix.so.0 lib/libfrix.a lib/pkgconfig/frix.pc lib/cmake/frix/frix-config.cmake; do
    [ -e "$prefix/$f" ] || { echo "not installed: $f"; exit 1; }
done
# With libfrix_mpi: its header, frix-mpi and the CMake component's targets, apart from
# frixTargets.cmake (which must not name MPI: a project without MPI loads it).
if [ -e "$prefix/lib/libfrix_mpi.so.0" ]; then
    for f in include/frix/frix_mpi.h bin/frix-mpi lib/cmake/frix/frix_mpi-targets.cmake; do
        [ -e "$prefix/$f" ] || { echo "not installed: $f"; exit 1; }
    done
fi
if grep -n 'MPI::' "$prefix/lib/cmake/frix/frixTargets.cmake"; then
    echo "frixTargets.cmake names MPI"
    exit 1
fi
"$prefix/bin/frix" --version

for way in cmake pkgconfig; do
    echo "== examples against the installed frix, found by $way"
    if [ "$way" = cmake ]; then
        set -- -DCMAKE_PREFIX_PATH="$prefix"
    else
        set -- -DFRIX_EXAMPLES_PKGCONFIG=ON
    fi
    PKG_CONFIG_PATH="$prefix/lib/pkgconfig" cmake --no-warn-unused-cli -S "$src/examples" -B "$work/$way" \
        -DCMAKE_BUILD_TYPE=Release -DCMAKE_C_FLAGS="$flags" -DCMAKE_Fortran_FLAGS="$flags" \
        -DCMAKE_EXE_LINKER_FLAGS="$flags" "$@" > "$work/$way.configure.log" ||
        { cat "$work/$way.configure.log"; exit 1; }
    cmake --build "$work/$way" -j2 > "$work/$way.build.log" || { cat "$work/$way.build.log"; exit 1; }
    "$work/$way/solve_csc"
    # detect_leaks=0: see example_plugin_host in tests/interfaces.cmake (sanitizer builds).
    ASAN_OPTIONS=detect_leaks=0 LD_LIBRARY_PATH="$prefix/lib" "$work/$way/plugin_host"
    if [ -e "$prefix/include/frix/frix.mod" ]; then
        [ -x "$work/$way/fortran_solve_local" ] || { echo "Fortran example not built ($way)"; exit 1; }
        "$work/$way/fortran_solve_local"
    fi
done
echo "installed package: both ways work"
