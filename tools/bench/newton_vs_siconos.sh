#!/bin/sh
# The Newton benchmark of issue 3: frix's nsn-ac, nsn-fb, nsn-nm and prox against Siconos 4.4's
# solvers of the same ids (NSN_AC 504, NSN_FB 513, NSN_NM 520, PROX 502) at tolerance 1e-8, on
# the local problems of ../shared/fclib and on ../shared/fclib-large. Not a test: it runs for
# tens of minutes. Each run is isolated and timed by `frix bench` (Siconos's r is measured by
# frix's error module, like frix's own); newton_summary.py then pairs the solvers and writes
# pairs.csv and the geometric-mean time ratio frix / Siconos on the problems both solve.
#
#   tools/bench/newton_vs_siconos.sh BUILD_DIR SHARED_DIR OUT_DIR [TIME_LIMIT_SMALL TIME_LIMIT_LARGE]
#
# Without Siconos installed, `frix bench` skips the siconos: solvers and the pairs are empty.
set -eu
build=$1
shared=$2
out=$3
small_limit=${4:-20}
large_limit=${5:-30}
here=$(dirname "$0")
solvers=nsn-ac,nsn-fb,nsn-nm,prox,siconos:NSN_AC,siconos:NSN_FB,siconos:NSN_NM,siconos:PROX
mkdir -p "$out"
# The limits are those of shared/fclib*/siconos-4.4-baseline.csv (20 s and 30 s).
"$build/tools/frix" bench "$shared/fclib/local" "$shared/fclib/converted" --solvers "$solvers" \
    --tol 1e-8 --time-limit "$small_limit" --out "$out/fclib" --no-plots
"$build/tools/frix" bench "$shared/fclib-large" --solvers "$solvers" \
    --tol 1e-8 --time-limit "$large_limit" --out "$out/fclib-large" --no-plots
python3 "$here/newton_summary.py" "$out/fclib/runs.csv" "$out/fclib-large/runs.csv" --out "$out/pairs.csv"
