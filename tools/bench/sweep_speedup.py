#!/usr/bin/python3
"""What threads buy gnsgs's sweeps: the time of one sweep on 1 and on T threads, and their
ratio. A sweep's time is (time of N sweeps - time of 20 sweeps) / (N - 20), so that the setup
(M, the domains, H and M^-1 H per contact) drops out; the periodic full checks stay in, as in a
solve. Runs alternate between the thread counts; medians of R runs.

    PYTHONPATH=build/python /usr/bin/python3 tools/bench/sweep_speedup.py FILE.hdf5
        [--threads T] [--sweeps N] [--runs R] [--freezing K]

FILE is a global problem of rigid bodies (the scale set of tools/bench/granular_scale_set.sh).
The tolerance is 0, so that every run makes exactly its N sweeps.
"""
import argparse
import statistics

import frix


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--sweeps", type=int, default=420)
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--freezing", type=int, default=0, help="gnsgs's freezing option (default 0: every contact swept)")
    a = ap.parse_args()
    if a.sweeps <= 20 or a.threads < 2 or a.runs < 1:
        ap.error("--sweeps must exceed 20, --threads be at least 2, --runs at least 1")
    problem = frix.load(a.file)

    def seconds(sweeps, threads):
        result = frix.solve(problem, solver="gnsgs", tol=0.0, max_iter=sweeps, threads=threads,
                            freezing=a.freezing, check_existence=False)
        if result.iterations != sweeps:
            raise SystemExit(f"{a.file}: stopped after {result.iterations} sweeps ({result.status.name})")
        return result.time

    per_sweep = {1: [], a.threads: []}
    for _ in range(a.runs):
        for threads in per_sweep:
            per_sweep[threads].append((seconds(a.sweeps, threads) - seconds(20, threads)) / (a.sweeps - 20))
    median = {t: statistics.median(v) for t, v in per_sweep.items()}
    print(f"{a.file}: {problem.contacts} contacts, {a.sweeps} sweeps, freezing {a.freezing}, {a.runs} runs")
    for t, v in per_sweep.items():
        print(f"  {t} thread(s): {1e3 * median[t]:.2f} ms a sweep (runs: {' '.join(f'{1e3 * x:.2f}' for x in sorted(v))})")
    print(f"  speed-up on {a.threads} threads: {median[1] / median[a.threads]:.2f}")


if __name__ == "__main__":
    main()
