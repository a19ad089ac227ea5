#!/usr/bin/env bash
# The scaling benchmark of docs/reports/benchmarks.md: piles of the granular client from about 10^3 to
# 10^6 contacts (tools/bench/granular_scale_set.sh), time to 1e-4 and 1e-6 for auto and nsgs
# (through W), gnsgs (without W), each of auto and gnsgs on 1 and 2 threads, and Siconos 4.4's
# GFC3D_NSGS_WR and GFC3D_ADMM as far as they finish; then the log-log plot of time against
# contacts with each solver's fitted slope (tools/bench/scaling_plot.py), spliced between the
# scaling markers of docs/reports/benchmarks.md (after a line naming this tool and the day), the
# plot and runs.csv copied to docs/reports/benchmarks/scaling/.
#
#   tools/bench/granular_scaling.sh [BUILD_DIR]      (from the repository root; default: build)
#
# Environment: SCALING_WORK (default BUILD_DIR/scaling), SCALING_SPHERES (default
# "300 2500 25000 250000"), SCALING_TIME_LIMIT (default 120 s per run), SCALING_TOLS (default
# "1e-4 1e-6").
set -euo pipefail
build=${1:-build}
work=${SCALING_WORK:-$build/scaling}
spheres=${SCALING_SPHERES:-300 2500 25000 250000}
limit=${SCALING_TIME_LIMIT:-120}
tols=${SCALING_TOLS:-1e-4 1e-6}
solvers="auto,auto@threads=2,nsgs,gnsgs,gnsgs@threads=2,siconos:GFC3D_NSGS_WR,siconos:GFC3D_ADMM"
here=$(cd "$(dirname "$0")" && pwd)
"$here/granular_scale_set.sh" "$build" "$work/problems" $spheres
runs=()
for tol in $tols; do
    "$build/tools/frix" bench "$work/problems" --solvers "$solvers" --tol "$tol" --time-limit "$limit" \
        --max-iter 1000000000 --out "$work/$tol" --no-plots -q
    runs+=("$work/$tol/runs.csv")
done
figures=docs/reports/benchmarks/scaling
mkdir -p "$figures"
for tol in $tols; do cp "$work/$tol/runs.csv" "$figures/runs-$tol.csv"; done
/usr/bin/python3 "$here/scaling_plot.py" "$figures" docs/reports/benchmarks.md "${runs[@]}"
