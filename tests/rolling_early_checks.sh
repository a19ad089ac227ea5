#!/bin/sh
# rolling-nsgs checks the full error after sweeps 1, 2, 4 and 8 as well as every 16 sweeps. On a
# pile at rest r drifts, its light error |dr| / |r| stays above a loose tolerance that the error
# already meets; a solve from r = 0 must still end at the first of those checks at or after the
# first sweep whose error meets the tolerance (found by runs capped at k sweeps: the iterates do
# not depend on the cap).
#   rolling_early_checks.sh GRANULAR FRIX TMPDIR
set -eu
granular=$1 frix=$2 tmp=$3
mkdir -p "$tmp"
pile="$tmp/early_checks_rest.hdf5"
"$granular" --spheres 300 --aspect 0.5 --rolling 1e-3 --steps 600 --every 1000 --settle --dump-step rest \
    --dump "$pile" > /dev/null
# solve ARGS...: "STATUS ITERATIONS" of rolling-nsgs from r = 0 at the tolerance 3e-2.
solve() {
    "$frix" solve "$pile" --solver rolling-nsgs --tol 3e-2 --json "$@" |
        sed -n 's/.*"status":"\([a-z_]*\)".*"iterations":\([0-9]*\).*/\1 \2/p'
}
first=0
for k in 1 2 3 4 5 6 7 8; do
    set -- $(solve --max-iter $k)
    if [ "$1" = converged ]; then first=$2; break; fi
done
[ "$first" -gt 0 ] || { echo "no sweep up to 8 meets 3e-2: the pile does not test the early checks" >&2; exit 1; }
due=1
while [ $due -lt "$first" ]; do due=$((due * 2)); done
set -- $(solve)
echo "first sweep that meets 3e-2: $first; the solve: $1 after $2 sweeps (at most $due)"
[ "$1" = converged ] && [ "$2" -ge "$first" ] && [ "$2" -le $due ]
