#!/usr/bin/python3
"""Fingerprints of every registered solver on a set of problem files, for refactorings that must
keep the same bits: one line per (file, solver) with the status, the iteration count, the error
and the other measures (as hex floats), the counters, the existence verdict, auto's stage records
(without their times) and a hash of r, u and v. Run it before and after a change and diff.

    PYTHONPATH=build/python tools/bit_identity.py FILE... > before.txt

Runs stop on iterations only (no time limit), so the output depends on the code alone."""
import argparse
import hashlib
import re
import sys

import numpy as np

import frix


def _timeless(note):
    return re.sub(r"\b[0-9][0-9.e+-]* s\b", "- s", note or "")


def fingerprint(problem, solver, tol, max_iter):
    try:
        res = frix.solve(problem, solver=solver, tol=tol, max_iter=max_iter)
    except frix.Error as e:
        return f"refused {type(e).__name__}"
    digest = hashlib.sha256()
    for x in (res.r, res.u, res.v):
        if x is not None:
            digest.update(np.ascontiguousarray(x, dtype=np.float64).tobytes())
    measures = " ".join(f"{k}={float(v).hex()}" for k, v in sorted(res.measures.items()))
    counters = " ".join(f"{k}={v}" for k, v in sorted(res.counters.items()))
    stages = ";".join(f"{s.solver},{int(s.status)},{s.iterations},{s.part},{s.part_contacts},"
                      f"{s.random_starts},{int(s.stopped_by_auto)},{float(s.error).hex()},{_timeless(s.note)}"
                      for s in res.stages)
    return (f"{res.status.name} it={res.iterations} err={float(res.error).hex()} {measures} "
            f"{counters} existence={int(res.existence)} r={digest.hexdigest()[:20]} stages=[{stages}]")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("files", nargs="+")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--max-iter", type=int, default=150)
    ap.add_argument("--solvers", default="", help="comma-separated names (default: all)")
    args = ap.parse_args()
    names = args.solvers.split(",") if args.solvers else [s.name for s in frix.solvers()]
    for path in args.files:
        try:
            problem = frix.load(path)
        except frix.Error as e:
            print(f"{path.rsplit('/', 1)[-1]} unreadable {type(e).__name__}", flush=True)
            continue
        for name in names:
            line = fingerprint(problem, name, args.tol, args.max_iter)
            print(f"{path.rsplit('/', 1)[-1]} {name} {line}", flush=True)


if __name__ == "__main__":
    sys.exit(main())
