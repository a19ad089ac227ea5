#!/bin/sh
# libfrix and libfrix_mpi of different releases, loaded together, refuse each other's handles
# cleanly (docs/abi.md, libfrix_mpi): a tree of the next release (-DFRIX_TEST_NEXT_RELEASE=ON:
# the version one patch later, a longer options record) is built beside this one (libfrix and
# libfrix_mpi only), and host_handles runs on 1 rank against each pair of the two trees'
# libraries, chosen through LD_LIBRARY_PATH.
#   release_mismatch.sh SOURCE BUILD LIBFRIX LIBFRIX_MPI WORK MPIEXEC HOST_HANDLES CC CXX [LAUNCHER]
# BUILD is this tree (its include/frix/frix_version.h), LIBFRIX and LIBFRIX_MPI its libraries.
set -u
src=$1 build=$2 libfrix=$3 libfrix_mpi=$4 work=$5 mpiexec=$6 host=$7 cc=$8 cxx=$9 launcher=${10:-}
next=$work/next
mkdir -p "$work"

if [ ! -f "$next/CMakeCache.txt" ]; then
    if ! cmake -S "$src" -B "$next" -DCMAKE_BUILD_TYPE=Release -DFRIX_TEST_NEXT_RELEASE=ON -DFRIX_WITH_MPI=ON \
            -DFRIX_BUILD_TESTS=OFF -DFRIX_FORTRAN=OFF -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
            -DCMAKE_C_COMPILER_LAUNCHER="$launcher" -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" \
            > "$work/configure.log" 2>&1; then
        tail -30 "$work/configure.log"
        rm -f "$next/CMakeCache.txt"
        echo "configuring the next release's tree failed"
        exit 1
    fi
fi
if ! cmake --build "$next" -j2 --target frix frix_mpi > "$work/build.log" 2>&1; then
    tail -30 "$work/build.log"
    echo "building the next release's tree failed"
    exit 1
fi

version_of() { sed -n 's/^#define FRIX_VERSION_STRING "\(.*\)"$/\1/p' "$1/include/frix/frix_version.h"; }
this=$(version_of "$build") later=$(version_of "$next")
if [ -z "$this" ] || [ -z "$later" ] || [ "$this" = "$later" ]; then
    echo "the two trees' versions are '$this' and '$later': they must differ"
    exit 1
fi

failed=0
# run NAME LIBFRIX LIBFRIX_MPI ARGS...: host_handles ARGS with that pair of library files.
run() {
    name=$1 lib=$2 mpilib=$3
    shift 3
    pair=$work/$name
    mkdir -p "$pair"
    ln -sf "$lib" "$pair/libfrix.so.0"
    ln -sf "$mpilib" "$pair/libfrix_mpi.so.0"
    # The loader must take both from the pair's folder (the program's run path must not win).
    for l in libfrix.so.0 libfrix_mpi.so.0; do
        if ! LD_LIBRARY_PATH=$pair ldd "$host" | grep -q "^[[:space:]]*$l => $pair/$l "; then
            echo "$name: $l is not loaded from $pair:"
            LD_LIBRARY_PATH=$pair ldd "$host" | grep libfrix
            failed=1
            return
        fi
    done
    echo "== $name: libfrix from $lib, libfrix_mpi from $mpilib: host_handles $*"
    if ! "$mpiexec" -n 1 env LD_LIBRARY_PATH="$pair" "$host" "$@"; then
        echo "$name: FAILED"
        failed=1
    fi
}

run same "$libfrix" "$libfrix_mpi" same "$this"
run next_release "$next/libfrix.so.0" "$next/libfrix_mpi.so.0" same "$later"
run newer_libfrix "$next/libfrix.so.0" "$libfrix_mpi" refused "$later" "$this"
run newer_libfrix_mpi "$libfrix" "$next/libfrix_mpi.so.0" refused "$this" "$later"
[ $failed -eq 0 ] && echo "release_mismatch: passed"
exit $failed
