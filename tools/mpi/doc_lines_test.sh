#!/bin/sh
# The mpirun/mpiexec lines of README.md and docs/*.md work as written when run as root:
#   doc_lines_test.sh SOURCE_DIR BUILD_DIR SHARED_DIR
# Every such line carries --allow-run-as-root (OpenMPI refuses root without it); the
# `frix-mpi solve` ones are run, from the source tree, with build/ read as BUILD_DIR and
# ../shared/ as SHARED_DIR (the Kapla problem one needs is skipped when absent). Run without
# OMPI_ALLOW_RUN_AS_ROOT in the environment, so that the flag itself is what is tested.
set -eu
src=$1 build=$2 shared=$3
cd "$src"
lines=$(grep -hE '^(mpirun|mpiexec) ' README.md docs/*.md)
[ -n "$lines" ] || { echo "no mpirun line found"; exit 1; }
missing=$(printf '%s\n' "$lines" | grep -v -- '--allow-run-as-root' || true)
if [ -n "$missing" ]; then
    printf 'without --allow-run-as-root:\n%s\n' "$missing"
    exit 1
fi
unset OMPI_ALLOW_RUN_AS_ROOT OMPI_ALLOW_RUN_AS_ROOT_CONFIRM
"$build/examples/make_example" "$build/example.hdf5" > /dev/null
ran=0
printf '%s\n' "$lines" | grep -- 'frix-mpi solve' > "$build/doc_mpirun_lines"
while IFS= read -r line; do
    cmd=$(printf '%s\n' "$line" | sed -e "s#\\.\\./shared/#$shared/#g" -e "s#\\bbuild/#$build/#g")
    for word in $cmd; do
        case $word in
            "$shared"/*) [ -e "$word" ] || { echo "skipped (no $word): $line"; continue 2; } ;;
        esac
    done
    echo "== $line"
    # mpirun reads stdin: it gets none, or it would eat the lines still to run.
    sh -c "$cmd" < /dev/null > "$build/doc_mpirun_out" 2>&1 || { cat "$build/doc_mpirun_out"; echo "FAILED: $line"; exit 1; }
    grep -q '^status  *converged' "$build/doc_mpirun_out" || { cat "$build/doc_mpirun_out"; exit 1; }
    ran=$((ran + 1))
done < "$build/doc_mpirun_lines"
[ "$ran" -gt 0 ] || { echo "no frix-mpi line ran"; exit 1; }
echo "$(printf '%s\n' "$lines" | wc -l) mpirun lines carry --allow-run-as-root; $ran frix-mpi lines ran as written"
