#!/bin/sh
# cmake --install into a scratch prefix, then build and run one kind of consumer against it:
#   cxx        a C++-only CMake project (LANGUAGES CXX) on frix::frix: configures without MPI
#   c          a C-only CMake project (LANGUAGES C) on frix::frix: the same
#   pkgconfig  a C program linked with `pkg-config --cflags --libs --static frix`: the flags
#              resolve, name no MPI, and link both with libfrix.so and with libfrix.a
#   mpi        a C project asking for COMPONENTS frix_mpi, run on 2 ranks; and a C++-only one
#              asking for it, which must be refused with the reason
#   install_consumers.sh KIND BUILD_DIR WORK_DIR EXTRA_FLAGS [MPIEXEC]
set -eu
kind=$1 build=$2 work=$3 flags=$4 mpiexec=${5:-mpiexec}
rm -rf "$work"
mkdir -p "$work"
prefix="$work/prefix"
cmake --install "$build" --prefix "$prefix" > "$work/install.log"

# The consumer's one source, valid C and C++: a one-contact local problem (W = I, pressed
# into the obstacle), solved to 1e-12; r_N must be 1.
cat > "$work/consumer.c" <<'EOF'
#include <frix/frix.h>
#include <math.h>
#include <stdio.h>

int main(void) {
    const int64_t colptr[4] = {0, 1, 2, 3}, rowind[3] = {0, 1, 2};
    const double values[3] = {1.0, 1.0, 1.0}, q[3] = {-1.0, 0.0, 0.0}, mu[1] = {0.5};
    double r[3] = {0.0, 0.0, 0.0}, u[3];
    frix_matrix *W = NULL;
    frix_problem *problem = NULL;
    frix_options *options = NULL;
    frix_info *info = NULL;
    frix_error err = frix_matrix_from_csc(3, 3, colptr, rowind, values, &W);
    if (!err) err = frix_problem_local(W, q, mu, 1, &problem);
    if (!err) err = frix_options_create(FRIX_SOLVER_NSGS, &options);
    if (!err) err = frix_options_set_double(options, FRIX_OPT_TOLERANCE, 1e-12);
    if (!err) err = frix_info_create(&info);
    if (!err) err = frix_solve(problem, options, r, u, NULL, info);
    int ok = !err && frix_info_status(info) == FRIX_STATUS_CONVERGED && fabs(r[0] - 1.0) < 1e-9;
    printf("consumer: %s, r_N = %.12f\n", err ? frix_last_error_message() : frix_status_string(frix_info_status(info)),
           r[0]);
    frix_info_free(info);
    frix_options_free(options);
    frix_problem_free(problem);
    frix_matrix_free(W);
    return ok ? 0 : 1;
}
EOF

# configure_and_build DIR: the project in DIR against the prefix, into DIR/b; its log in DIR.
configure_and_build() {
    cmake --no-warn-unused-cli -S "$1" -B "$1/b" -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_C_FLAGS="$flags" -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" \
        > "$1/configure.log" 2>&1 || { cat "$1/configure.log"; return 1; }
    cmake --build "$1/b" > "$1/build.log" 2>&1 || { cat "$1/build.log"; return 1; }
}

# no_mpi DIR: the configure neither looked for MPI nor left anything of it in the cache.
no_mpi() {
    if grep -E '\bMPI' "$1/configure.log" || grep -E '^MPI_|^MPIEXEC' "$1/b/CMakeCache.txt"; then
        echo "$1: MPI was looked for, though only frix::frix is used"
        exit 1
    fi
}

case $kind in
cxx|c)
    dir="$work/$kind"
    mkdir -p "$dir"
    if [ "$kind" = cxx ]; then lang=CXX src=consumer.cpp; else lang=C src=consumer.c; fi
    cp "$work/consumer.c" "$dir/$src"
    cat > "$dir/CMakeLists.txt" <<EOF
cmake_minimum_required(VERSION 3.25)
project(frix_consumer LANGUAGES $lang)
find_package(frix 0.1 CONFIG REQUIRED)
if(TARGET frix::frix_mpi OR TARGET MPI::MPI_C)
  message(FATAL_ERROR "frix::frix_mpi or MPI defined though not asked for")
endif()
add_executable(consumer $src)
target_link_libraries(consumer PRIVATE frix::frix m)
EOF
    configure_and_build "$dir"
    no_mpi "$dir"
    "$dir/b/consumer"
    echo "$lang-only project on frix::frix: configured without MPI, built and ran"
    ;;
pkgconfig)
    pc="env PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config"
    pcflags=$($pc --cflags --libs --static frix)
    echo "pkg-config --cflags --libs --static frix: $pcflags"
    # (the install prefix is taken out first: its own path may hold the letters)
    case $(printf '%s' "$pcflags" | sed "s|$prefix||g") in
        *mpi*|*MPI*) echo "the static flags pull MPI"; exit 1 ;;
    esac
    # Against libfrix.so (what -lfrix picks when both are installed).
    # shellcheck disable=SC2086
    cc $flags "$work/consumer.c" -o "$work/consumer_shared" $pcflags -Wl,-rpath,"$prefix/lib"
    "$work/consumer_shared"
    ldd "$work/consumer_shared" | grep -q "$prefix/lib/libfrix.so" || { echo "not linked to the installed libfrix.so"; exit 1; }
    # Against libfrix.a: its dependencies must all come from the flags.
    static_flags=$(printf '%s\n' "$pcflags" | sed "s#-lfrix\\b#$prefix/lib/libfrix.a#")
    # shellcheck disable=SC2086
    cc $flags "$work/consumer.c" -o "$work/consumer_static" $static_flags
    "$work/consumer_static"
    if ldd "$work/consumer_static" | grep -E 'libfrix|libmpi'; then
        echo "the libfrix.a build links libfrix.so or libmpi"
        exit 1
    fi
    echo "pkg-config --static: no MPI, linked with libfrix.so and with libfrix.a, both ran"
    ;;
mpi)
    [ -e "$prefix/lib/cmake/frix/frix_mpi-targets.cmake" ] || { echo "frix_mpi not installed"; exit 1; }
    dir="$work/mpi"
    mkdir -p "$dir"
    # Each rank owns one contact (W = I): every rank's r_N must be 1.
    cat > "$dir/consumer_mpi.c" <<'EOF'
#include <frix/frix.h>
#include <frix/frix_mpi.h>
#include <math.h>
#include <stdio.h>

int main(int argc, char **argv) {
    int rank = 0, size = 1, ok = 0;
    MPI_Init(&argc, &argv);
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    const int64_t row_ptr[2] = {0, 1}, block_col[1] = {rank};
    const double block[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1}, q[3] = {-1.0, 0.0, 0.0}, mu[1] = {0.5};
    double r[3] = {0, 0, 0}, u[3];
    frix_mpi_context *ctx = NULL;
    frix_mpi_problem *p = NULL;
    frix_options *opts = NULL;
    frix_info *info = NULL;
    if (!frix_mpi_context_create(MPI_COMM_WORLD, &ctx) &&
        !frix_mpi_problem_local(ctx, rank, 1, row_ptr, block_col, block, q, mu, &p) &&
        !frix_options_create(FRIX_SOLVER_NSGS, &opts) && !frix_options_set_double(opts, FRIX_OPT_TOLERANCE, 1e-12) &&
        !frix_info_create(&info) && !frix_mpi_solve(p, opts, r, u, info))
        ok = frix_info_status(info) == FRIX_STATUS_CONVERGED && fabs(r[0] - 1.0) < 1e-9;
    else
        fprintf(stderr, "rank %d: %s\n", rank, frix_mpi_last_error_message());
    MPI_Allreduce(MPI_IN_PLACE, &ok, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (rank == 0) printf("consumer_mpi: %d ranks, %s\n", size, ok ? "converged, r_N = 1 on every rank" : "FAILED");
    frix_info_free(info);
    frix_options_free(opts);
    frix_mpi_problem_free(p);
    frix_mpi_context_free(ctx);
    MPI_Finalize();
    return ok ? 0 : 1;
}
EOF
    cat > "$dir/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(frix_consumer_mpi LANGUAGES C)
find_package(frix 0.1 CONFIG REQUIRED COMPONENTS frix_mpi)
add_executable(consumer_mpi consumer_mpi.c)
target_link_libraries(consumer_mpi PRIVATE frix::frix_mpi frix::frix m)
EOF
    configure_and_build "$dir"
    "$mpiexec" -n 2 "$dir/b/consumer_mpi"
    # A C++-only project cannot have frix_mpi (MPI is found through its C bindings): refused,
    # with the reason, and nothing else goes wrong.
    refused="$work/mpi_cxx"
    mkdir -p "$refused"
    cat > "$refused/CMakeLists.txt" <<'EOF'
cmake_minimum_required(VERSION 3.25)
project(frix_consumer_mpi_cxx LANGUAGES CXX)
find_package(frix 0.1 CONFIG REQUIRED COMPONENTS frix_mpi)
EOF
    if cmake -S "$refused" -B "$refused/b" -DCMAKE_PREFIX_PATH="$prefix" > "$refused/configure.log" 2>&1; then
        echo "frix_mpi accepted in a C++-only project"
        exit 1
    fi
    grep -q 'needs the C language enabled' "$refused/configure.log" ||
        { cat "$refused/configure.log"; echo "refused without the reason"; exit 1; }
    echo "COMPONENTS frix_mpi: built and ran on 2 ranks; refused with its reason in a C++-only project"
    ;;
*)
    echo "unknown kind $kind"
    exit 2
    ;;
esac
