#!/usr/bin/env bash
# Regenerates the results of docs/benchmarks.md: four campaigns (every
# registered frix solver and Siconos 4.4's nine) over the shared FCLIB problems at tolerance
# 1e-4, 1e-6 and 1e-8 and over the larger problems of fclib-large at 1e-8, two at simulation
# tolerances (1e-4 and 1e-6) over fclib-large and generated pyramids of spheres (960, 3312
# and 15600 contacts) with the solvers that can be the best there, fclib-large alone at 1e-6
# with those solvers and a longer cap (large-1e-6-long), and one of global problems
# (the shared FCLIB global ones and generated elastic grids of 1200 to 99825 dofs, frix's
# solvers for them and Siconos 4.4's global ones) at 1e-8; their tables spliced
# between the markers of docs/benchmarks.md, their plots and runs.csv copied to
# docs/benchmarks/<campaign>/; then auto against the best solver of each library, problem by
# problem, over the two 1e-8 campaigns (tools/bench/auto_summary.py), with the performance
# profile of all the solvers over both (docs/benchmarks/all-1e-8/). The traces stay in the
# work directory.
#
#   tools/bench/bench_docs.sh [BUILD_DIR]      (from the repository root; default: build)
#
# Environment: FRIX_SHARED_DIR (default ../shared), BENCH_WORK (default BUILD_DIR/bench-docs),
# BENCH_TIME_LIMIT (default 20 s per run), BENCH_LARGE_TIME_LIMIT (default 30 s per run on
# fclib-large at 1e-8), BENCH_LONG_TIME_LIMIT (default 150 s per run in large-1e-6-long),
# BENCH_GLOBAL_TIME_LIMIT (default 60 s per run on the global ones), BENCH_MAX_ITER (iterations per run, default 1000000000: the time limit is what
# ends a run, so that a solver that needs millions of fast sweeps, NSGS on RockPile_tob1,
# is judged by the clock), BENCH_JOBS (default 1), BENCH_CAMPAIGNS (default "1e-4 1e-6 1e-8
# large large-1e-4 large-1e-6 large-1e-6-long global"),
# BENCH_REUSE=1 (redo the report of a campaign whose BENCH_WORK/<campaign>/runs.csv exists,
# e.g. after rows were added to it by hand, instead of running it again).
set -euo pipefail
build=${1:-build}
shared=${FRIX_SHARED_DIR:-../shared}
work=${BENCH_WORK:-$build/bench-docs}
limit=${BENCH_TIME_LIMIT:-20}
large_limit=${BENCH_LARGE_TIME_LIMIT:-30}
long_limit=${BENCH_LONG_TIME_LIMIT:-150}
global_limit=${BENCH_GLOBAL_TIME_LIMIT:-60}
max_iter=${BENCH_MAX_ITER:-1000000000}
jobs=${BENCH_JOBS:-1}
campaigns=${BENCH_CAMPAIGNS:-1e-4 1e-6 1e-8 large large-1e-4 large-1e-6 large-1e-6-long global}
frix="$build/tools/frix"
doc=docs/benchmarks.md

[ -x "$frix" ] || { echo "bench_docs.sh: $frix not found: build first" >&2; exit 2; }
[ -f "$doc" ] || { echo "bench_docs.sh: run from the repository root ($doc not found)" >&2; exit 2; }
[ -x "$build/tools/frix-siconos" ] ||
    echo "bench_docs.sh: warning: frix-siconos not built: the tables will lack Siconos" >&2

# splice FILE MARKER BLOCK: replaces what lies between "<!-- MARKER begin -->" and
# "<!-- MARKER end -->" in FILE with the contents of BLOCK.
splice() {
    awk -v begin="<!-- $2 begin -->" -v end="<!-- $2 end -->" -v block="$3" '
        $0 == begin { print; while ((getline line < block) > 0) print line; skip = 1; next }
        $0 == end { skip = 0 }
        !skip { print }' "$1" > "$1.new"
    mv "$1.new" "$1"
}

versions() {
    printf '%s, Siconos %s; %s cores, %s job(s)' "$("$frix" --version)" \
        "$(dpkg-query -W -f='${Version}' libsiconos-numerics-dev 2>/dev/null || echo 'not installed')" \
        "$(env -u OMP_NUM_THREADS -u OMP_THREAD_LIMIT nproc)" "$jobs"  # (nproc obeys OMP_NUM_THREADS)
}

# The pyramids of spheres of the simulation-tolerance campaigns (hyperstatic piles that
# NSGS does not finish), written once into the work directory.
pyramids() {
    mkdir -p "$work/scenes"
    for layers in 8 12 20; do
        [ -f "$work/scenes/pyramid-$layers.hdf5" ] ||
            "$build/examples/frix_scene" spheres "$work/scenes/pyramid-$layers.hdf5" --count "$layers" --local >/dev/null
    done
}

# Elastic grids, a deformable body in global form (frix_scene elastic-grid): 1200, 12000,
# 48000 and 99825 dofs, 100 to 3025 contacts, written once into the work directory.
grids() {
    mkdir -p "$work/grids"
    for size in "10 10 4" "20 20 10" "40 40 10" "55 55 11" "30 30 2" "60 60 3" "80 80 2"; do
        set -- $size
        [ -f "$work/grids/elastic-grid-$1x$2x$3.hdf5" ] ||
            "$build/examples/frix_scene" elastic-grid "$work/grids/elastic-grid-$1x$2x$3.hdf5" "$1" "$2" "$3" >/dev/null
    done
}

# Every frix solver and every Siconos solver, but at simulation tolerances on fclib-large and
# the pyramids: the ones that were the fastest on some problem of these families (Siconos's
# NSN_AC reached neither 1e-4 nor 1e-6 on any of them in 20 s).
simulation_solvers=auto,nsgs,nsgs-v,admm,ipm,prox,siconos:NSGS,siconos:ADMM,siconos:PROX
for campaign in $campaigns; do
    solvers=all,siconos:all
    case $campaign in
        large) dirs=("$shared/fclib-large"); tol=1e-8; tl=$large_limit ;;
        large-1e-4 | large-1e-6)
            pyramids
            dirs=("$shared/fclib-large" "$work/scenes"); tol=${campaign#large-}; tl=$limit
            solvers=$simulation_solvers ;;
        large-1e-6-long)
            # The same solvers on fclib-large alone with a longer cap: at 20 s one of its
            # problems is solved by none of them.
            dirs=("$shared/fclib-large"); tol=1e-6; tl=$long_limit
            solvers=$simulation_solvers ;;
        global)
            grids
            dirs=("$shared/fclib/global" "$work/grids"); tol=1e-8; tl=$global_limit
            solvers=auto,gnsn-ac,gadmm,gnsn-al,nsgs,nsgs-v,admm,ipm,siconos:GFC3D_NSN_AC,siconos:GFC3D_NSN_AC_WR,siconos:GFC3D_NSGS_WR,siconos:GFC3D_PROX_WR,siconos:GFC3D_ADMM,siconos:GFC3D_IPM ;;
        *) dirs=("$shared/fclib/local" "$shared/fclib/converted"); tol=$campaign; tl=$limit ;;
    esac
    out="$work/$campaign"
    start=$SECONDS
    if [ "${BENCH_REUSE:-0}" = 1 ] && [ -f "$out/runs.csv" ]; then
        "$frix" bench --report "$out"
        how="report redone from the campaign's runs.csv"
    else
        "$frix" bench "${dirs[@]}" --solvers "$solvers" --tol "$tol" --time-limit "$tl" \
            --max-iter "$max_iter" --jobs "$jobs" --out "$out"
        wall=$((SECONDS - start))
        how=$(printf 'campaign wall time %dm%02ds' $((wall / 60)) $((wall % 60)))
    fi
    [ -f "$out/plots/profile.png" ] ||
        { echo "bench_docs.sh: no plots (python3-matplotlib missing?)" >&2; exit 1; }
    mkdir -p "docs/benchmarks/$campaign"
    cp "$out/runs.csv" "$out/summary.md" "$out"/plots/*.png "$out"/plots/*.svg "docs/benchmarks/$campaign/"
    # The cap the runs had (a reused campaign may predate BENCH_MAX_ITER's value).
    cap=$(awk -F, 'NR == 2 { print $13 }' "$out/runs.csv")
    {
        printf 'Generated on %s by `tools/bench/bench_docs.sh` (%s; tolerance %s, %s s and at most %s iterations per run; %s).\n\n' \
            "$(date -u +%Y-%m-%d)" "$(versions)" "$tol" "$tl" "$cap" "$how"
        cat "$out/summary.md"
    } > "$out/block.md"
    splice "$doc" "bench $campaign" "$out/block.md"
done

# auto against the best of each library, and the profile of every solver, over both 1e-8
# campaigns together.
if [ -f "$work/1e-8/runs.csv" ] && [ -f "$work/large/runs.csv" ]; then
    all="$work/all-1e-8"
    mkdir -p "$all"
    cp "$work/1e-8/runs.csv" "$all/runs.csv"
    tail -n +2 "$work/large/runs.csv" >> "$all/runs.csv"
    cp "$work/1e-8/traces.csv" "$all/traces.csv"
    tail -n +2 "$work/large/traces.csv" >> "$all/traces.csv"
    "$frix" bench --report "$all"
    mkdir -p docs/benchmarks/all-1e-8
    cp "$all"/plots/profile.png "$all"/plots/profile.svg docs/benchmarks/all-1e-8/
    tools/bench/auto_summary.py "$work/1e-8/runs.csv" "$work/large/runs.csv" > "$all/auto.md"
    splice "$doc" "bench auto" "$all/auto.md"
fi
echo "bench_docs.sh: $doc and docs/benchmarks/ updated"
