#!/usr/bin/env bash
# The settled-steps benchmark (issue 51; its section in docs/reports/benchmarks.md): time steps of piles
# at or near rest, dumped by the granular client, each solved from the client's previous answer
# (the file's guess 1, as a time-stepping host starts) by frix and by Siconos 4.4 in the same
# campaign, to 1e-8 with every run's error-against-time trace: work-precision from 1e-2 to 1e-8.
#
#   tools/bench/settled_steps.sh [BUILD_DIR [problems]]   (from the repository root; default: build)
#
# With `problems`, only the steps are written (the pours take most of an hour on 2 cores, and
# need no quiet machine; the campaigns do).
#
# The steps (a file already in SETTLED_WORK/problems is kept):
# - rolling-N: a low pour of N spheres with rolling resistance (mu_r = 1e-3 m), dumped at the
#   first step after which every grain is slower than 0.1 radius/s (`--dump-step rest`);
#   N = 3500, 10000, 35000 give about 10^4, 3 10^4 and 10^5 contacts. Both forms: the global
#   problem (H and M, what the client holds) and the local one (W formed).
# - coulomb-N: the pours of N = 1000 and 10000 spheres without rolling resistance at step 150,
#   as the 10^4 one of notes/2026-11-28-settled-piles.md (gnsgs with momentum, sweeps capped at
#   3000 a step, so the warm start is as inexact as in a simulation with a cap). Such piles
#   never rest: without rolling resistance spheres keep rolling.
# Four campaigns, one per family and form, each with the solvers that take it: rolling global
# and local, Coulomb global and local. Then tools/bench/settled_table.py splices a table per
# family between the settled markers of docs/reports/benchmarks.md, and the runs.csv files and
# work-precision plots go to docs/reports/benchmarks/settled/.
#
# Environment: SETTLED_WORK (default BUILD_DIR/settled), SETTLED_ROLLING (default
# "3500 10000 35000"), SETTLED_COULOMB (default "1000 10000"), SETTLED_TIME_LIMIT (default 60 s
# per run), SETTLED_TOL (default 1e-8), SETTLED_REPORT (default docs/reports/benchmarks.md;
# empty: tables printed, nothing in docs/ changed).
set -euo pipefail
build=${1:-build}
work=${SETTLED_WORK:-$build/settled}
rolling=${SETTLED_ROLLING-3500 10000 35000}
coulomb=${SETTLED_COULOMB-1000 10000}
limit=${SETTLED_TIME_LIMIT:-60}
tol=${SETTLED_TOL:-1e-8}
report=${SETTLED_REPORT-docs/reports/benchmarks.md}
client="$build/examples/granular"
here=$(cd "$(dirname "$0")" && pwd)
[ -x "$client" ] || { echo "settled_steps.sh: $client is not built" >&2; exit 2; }
problems="$work/problems"
mkdir -p "$problems"/{rolling-global,rolling-local,coulomb-global,coulomb-local}

# dump NAME CLIENT_ARGS...: the step's two forms, written once.
dump() {
    local name=$1 family=${1%%-*}
    shift
    local global="$problems/$family-global/$name.hdf5" local="$problems/$family-local/$name.local.hdf5"
    if [ -f "$global" ] && [ -f "$local" ]; then
        echo "kept $name"
        return
    fi
    local start
    start=$(date +%s)
    "$client" "$@" --threads 2 --quiet --dump "$global.part" --dump-local "$local.part"
    mv "$global.part" "$global"
    mv "$local.part" "$local"
    echo "wrote $name ($(( $(date +%s) - start )) s)"
}

for n in $rolling; do
    dump "rolling-$n" --spheres "$n" --aspect 0.5 --floor 3 --step 4e-3 --rolling 1e-3 --steps 2000 \
        --settle --dump-step rest
done
for n in $coulomb; do
    dump "coulomb-$n" --spheres "$n" --steps 151 --solver gnsgs --set acceleration=1 --max-iter 3000 \
        --dump-step 150
done

[ "${2:-}" = problems ] && exit 0

run() {  # run FAMILY SOLVERS
    local dir="$problems/$1"
    ls "$dir"/*.hdf5 >/dev/null 2>&1 || return 0
    "$build/tools/frix" bench "$dir" --solvers "$2" --guess 1 --tol "$tol" --time-limit "$limit" \
        --max-iter 1000000000 --out "$work/$1" -q
}
run rolling-global "auto,auto@threads=2,rolling-nsgs@threads=2,siconos:GRFC3D_NSGS_WR"
run rolling-local "auto,rolling-nsgs,siconos:RFC3D_NSGS,siconos:RFC3D_ADMM"
run coulomb-global "auto,auto@threads=2,gnsgs@threads=2,siconos:GFC3D_NSGS_WR,siconos:GFC3D_ADMM,siconos:GFC3D_NSN_AC"
run coulomb-local "auto,nsgs-v,siconos:NSGS,siconos:PROX,siconos:ADMM,siconos:NSN_AC"

families=()
for f in rolling-global rolling-local coulomb-global coulomb-local; do
    if [ -f "$work/$f/runs.csv" ]; then families+=("$f"); fi
done
if [ ${#families[@]} -eq 0 ]; then
    echo "settled_steps.sh: no campaign ran (no steps in $problems)" >&2
    exit 1
fi
if [ -z "$report" ]; then
    /usr/bin/python3 "$here/settled_table.py" - "$work" "${families[@]}"
    exit 0
fi
figures=docs/reports/benchmarks/settled
mkdir -p "$figures"
for f in "${families[@]}"; do
    mkdir -p "$figures/$f"
    cp "$work/$f/runs.csv" "$figures/$f/runs.csv"
    for p in "$work/$f"/plots/work_precision.{png,svg}; do
        [ -f "$p" ] && cp "$p" "$figures/$f/"
    done
done
/usr/bin/python3 "$here/settled_table.py" "$report" "$work" "${families[@]}"
