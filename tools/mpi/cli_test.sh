#!/bin/sh
# frix-mpi solve takes frix solve's options under their names and prints its report:
#   cli_test.sh MPIEXEC NP FRIX_MPI FRIX MAKE_EXAMPLE GRANULAR WORK_DIR
# On NP ranks: --output (and --out, -o) writes a file frix reads; --json prints one object
# with the fields of frix solve --json (and "mpi"); --tol, --max-iter, --time-limit, --set
# and --solver act as they do for frix solve; --help exits 0; bad options exit 2.
set -eu
mpiexec=$1 np=$2 frix_mpi=$3 frix=$4 make_example=$5 granular=$6 work=$7
rm -rf "$work"
mkdir -p "$work"
run() { "$mpiexec" -n "$np" "$frix_mpi" "$@"; }
fail() { echo "FAIL: $*"; exit 1; }
# json FILE EXPR: evaluates the Python expression EXPR on the object j read from FILE.
json() { python3 -c "import json, sys; j = json.load(open(sys.argv[1])); sys.exit(0 if ($2) else 1)" "$1" ||
         fail "$1: not ($2): $(cat "$1")"; }

"$make_example" "$work/example.hdf5" > /dev/null
problem="$work/example.hdf5"

run --help > "$work/help" || fail "--help exits non-zero"
for o in --solver --tol --max-iter --time-limit --set --parts --output --json --verbose; do
    grep -q -- "$o" "$work/help" || fail "--help does not mention $o"
done

# The text report, and --output, --out and -o writing a solution frix reads.
for o in --output --out -o; do
    rm -f "$work/solved.hdf5"
    run solve "$problem" --tol 1e-8 "$o" "$work/solved.hdf5" > "$work/text" || fail "$o: not converged"
    grep -q '^status  *converged' "$work/text" || fail "$o: no converged status line"
    grep -q "^written to  *$work/solved.hdf5" "$work/text" || fail "$o: no 'written to' line"
    "$frix" info "$work/solved.hdf5" > /dev/null || fail "$o: frix cannot read the file written"
done

# --json: frix solve's fields, all of them, with the same meaning.
"$frix" solve "$problem" --solver nsgs --tol 1e-8 --json > "$work/serial.json"
run solve "$problem" --tol 1e-8 --json --output "$work/solved.hdf5" > "$work/mpi.json"
python3 - "$work/serial.json" "$work/mpi.json" <<'EOF' || exit 1
import json, sys
serial, mpi = (json.load(open(f)) for f in sys.argv[1:3])
def keys(o, at=""):
    return {at + k for k in o} | {k2 for k, v in o.items() if isinstance(v, dict) for k2 in keys(v, at + k + ".")}
missing = keys(serial) - keys(mpi)
extra = {k for k in keys(mpi) - keys(serial) if not k.startswith("mpi")}
assert not missing and not extra, f"fields missing {sorted(missing)}, extra {sorted(extra)}"
for k in ("file", "kind", "contacts", "contact_dofs", "dofs", "solver", "solver_id", "status", "converged",
          "error_measure", "tolerance"):
    assert serial[k] == mpi[k], f"{k}: frix solve {serial[k]!r}, frix-mpi {mpi[k]!r}"
assert mpi["error"] <= mpi["tolerance"] and mpi["measures"]["error_relative"] is not None, mpi
assert mpi["output"] == sys.argv[2].replace("mpi.json", "solved.hdf5"), mpi["output"]
EOF
json "$work/mpi.json" "j['mpi']['ranks'] == $np and j['mpi']['form'] == 'W'"

# --max-iter: exit 1, the status and the count frix solve would give.
status=0
run solve "$problem" --max-iter 2 --json > "$work/max_iter.json" || status=$?
[ "$status" -eq 1 ] || fail "--max-iter 2: exit $status, expected 1"
json "$work/max_iter.json" "j['status'] == 'max_iter' and j['iterations'] == 2 and not j['converged'] and j['existence'] != 'not checked'"

# --tol, --time-limit and --set reach the solver, --set by number or by a choice's name.
run solve "$problem" --tol 1e-3 --time-limit 60 --set error_measure=0 --json > "$work/set.json"
json "$work/set.json" "j['tolerance'] == 1e-3 and j['error_measure'] == 'siconos' and j['converged']"
run solve "$problem" --set error_measure=q_relative --json > "$work/set-name.json"
json "$work/set-name.json" "j['error_measure'] == 'q_relative'"

# --solver: gnsn-ac on a global problem (a granular step), its rows on the ranks.
"$granular" --spheres 60 --steps 20 --quiet --dump-step 19 --dump "$work/global.hdf5"
run solve "$work/global.hdf5" --solver gnsn-ac --tol 1e-6 --json > "$work/global.json"
json "$work/global.json" "j['kind'] == 'global' and j['solver'] == 'gnsn-ac' and j['dofs'] == 360 and j['mpi']['form'] == 'global' and j['converged']"

# Refused: exit 2.
for bad in "--tol x" "--set nosuch=1" "--solver nosuch" "--output" "--bogus"; do
    status=0
    # shellcheck disable=SC2086
    run solve "$problem" $bad > /dev/null 2>&1 || status=$?
    [ "$status" -eq 2 ] || fail "'$bad': exit $status, expected 2"
done
echo "frix-mpi solve on $np ranks: frix solve's options and report"
