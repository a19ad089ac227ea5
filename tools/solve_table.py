#!/usr/bin/env python3
"""Solve FCLIB files with `frix solve --json` several times and print one CSV row per file:
median time, and the iterations, status and error of the runs (identical across runs, since
solves are deterministic). A benchmark, not a test.

    tools/solve_table.py --frix build/tools/frix --runs 3 --tol 1e-8 FILES_OR_DIRS...
"""
import argparse
import json
import os
import statistics
import subprocess
import sys


def problem_files(paths):
    for path in paths:
        if os.path.isdir(path):
            for name in sorted(os.listdir(path)):
                if name.endswith(".hdf5"):
                    yield os.path.join(path, name)
        else:
            yield path


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--frix", default="build/tools/frix")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--tol", default="1e-8")
    ap.add_argument("--solver", default="nsgs")
    ap.add_argument("--time-limit", default="0")
    ap.add_argument("--max-iter", default=None)
    ap.add_argument("paths", nargs="+")
    args = ap.parse_args()

    out = sys.stdout
    out.write("file,contacts,solver,status,iterations,error,median_time_s,runs\n")
    for path in problem_files(args.paths):
        cmd = [args.frix, "solve", path, "--json", "--solver", args.solver, "--tol", args.tol,
               "--time-limit", args.time_limit]
        if args.max_iter:
            cmd += ["--max-iter", args.max_iter]
        times, last = [], None
        for _ in range(args.runs):
            proc = subprocess.run(cmd, capture_output=True, text=True)
            if proc.returncode == 2:
                last = None
                sys.stderr.write(f"{os.path.basename(path)}: {proc.stderr.strip()}\n")
                break
            last = json.loads(proc.stdout)
            times.append(last["time"])
        if last is None:
            out.write(f"{os.path.basename(path)},,{args.solver},error,,,,0\n")
            continue
        out.write(f"{os.path.basename(path)},{last['contacts']},{last['solver']},{last['status']},"
                  f"{last['iterations']},{last['error']:.3e},{statistics.median(times):.4g},{len(times)}\n")
        out.flush()


if __name__ == "__main__":
    main()
