#!/usr/bin/env bash
# The scale set: piles of the granular client (examples/granular) dumped as FCLIB files, from
# about 10^4 to 10^6 contacts. Each is step 80 of a pour (seed 1, h = 2e-3, mu = 0.5),
# stepped with gnsgs on 2 threads and at most 300 sweeps a step (the intermediate steps need
# not converge: only the dumped problem is kept, and it is the same on every machine).
#
#   tools/bench/granular_scale_set.sh [BUILD_DIR [OUT_DIR [SPHERES...]]]
#
# Defaults: BUILD_DIR build, OUT_DIR BUILD_DIR/scale-set, SPHERES "2500 25000 250000"
# (about 1e4, 1e5 and 1e6 contacts). A file already there is kept. Files are named
# granular-SPHERES.hdf5; too large to commit.
set -euo pipefail
build=${1:-build}
out=${2:-$build/scale-set}
shift $(( $# > 2 ? 2 : $# ))
spheres=${*:-2500 25000 250000}
client="$build/examples/granular"
[ -x "$client" ] || { echo "granular_scale_set.sh: $client is not built" >&2; exit 2; }
mkdir -p "$out"
for n in $spheres; do
    file="$out/granular-$n.hdf5"
    if [ -f "$file" ]; then
        echo "kept $file"
        continue
    fi
    start=$(date +%s)
    "$client" --spheres "$n" --steps 80 --solver gnsgs --threads 2 --max-iter 300 --quiet \
        --dump-step 80 --dump "$file.part"
    mv "$file.part" "$file"
    echo "wrote $file ($(( $(date +%s) - start )) s)"
done
