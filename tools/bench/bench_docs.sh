#!/usr/bin/env bash
# Regenerates the results of docs/benchmarks.md: the two campaigns over the shared FCLIB
# problems (tolerance 1e-4 and 1e-8; every registered frix solver and Siconos 4.4's nine),
# their tables spliced between the markers of docs/benchmarks.md, and their plots and
# runs.csv copied to docs/benchmarks/<tol>/. The traces stay in the work directory.
#
#   tools/bench/bench_docs.sh [BUILD_DIR]      (from the repository root; default: build)
#
# Environment: FRIX_SHARED_DIR (default ../shared), BENCH_WORK (default BUILD_DIR/bench-docs),
# BENCH_TIME_LIMIT (default 10 s per run), BENCH_JOBS (default 1).
set -euo pipefail
build=${1:-build}
shared=${FRIX_SHARED_DIR:-../shared}
work=${BENCH_WORK:-$build/bench-docs}
limit=${BENCH_TIME_LIMIT:-10}
jobs=${BENCH_JOBS:-1}
frix="$build/tools/frix"
doc=docs/benchmarks.md

[ -x "$frix" ] || { echo "bench_docs.sh: $frix not found: build first" >&2; exit 2; }
[ -f "$doc" ] || { echo "bench_docs.sh: run from the repository root ($doc not found)" >&2; exit 2; }
[ -x "$build/tools/frix-siconos" ] ||
    echo "bench_docs.sh: warning: frix-siconos not built: the tables will lack Siconos" >&2

for tol in 1e-4 1e-8; do
    start=$SECONDS
    "$frix" bench "$shared/fclib/local" "$shared/fclib/converted" --solvers all,siconos:all \
        --tol "$tol" --time-limit "$limit" --jobs "$jobs" --out "$work/$tol"
    wall=$((SECONDS - start))
    [ -f "$work/$tol/plots/profile.png" ] ||
        { echo "bench_docs.sh: no plots (python3-matplotlib missing?)" >&2; exit 1; }
    mkdir -p "docs/benchmarks/$tol"
    cp "$work/$tol/runs.csv" "$work/$tol/summary.md" "$work/$tol"/plots/*.png \
        "$work/$tol"/plots/*.svg "docs/benchmarks/$tol/"
    {
        printf 'Generated on %s by `tools/bench/bench_docs.sh` (%s, Siconos %s; %s cores, %s job(s); campaign wall time %dm%02ds).\n\n' \
            "$(date -u +%Y-%m-%d)" "$("$frix" --version)" \
            "$(dpkg-query -W -f='${Version}' libsiconos-numerics-dev 2>/dev/null || echo 'not installed')" \
            "$(nproc)" "$jobs" $((wall / 60)) $((wall % 60))
        cat "$work/$tol/summary.md"
    } > "$work/$tol/block.md"
    # Replace what lies between "<!-- bench TOL begin -->" and "<!-- bench TOL end -->".
    awk -v begin="<!-- bench $tol begin -->" -v end="<!-- bench $tol end -->" \
        -v block="$work/$tol/block.md" '
        $0 == begin { print; while ((getline line < block) > 0) print line; skip = 1; next }
        $0 == end { skip = 0 }
        !skip { print }' "$doc" > "$doc.new"
    mv "$doc.new" "$doc"
done
echo "bench_docs.sh: $doc and docs/benchmarks/ updated"
