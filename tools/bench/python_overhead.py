#!/usr/bin/python3
"""What a solve through the Python package costs above the C call: N solves of a one-contact
problem through frix.Solver, timed in Python, against the library's own time of the same
solves (frix_info_solve_time, measured inside the C call). Medians of 5 runs.

    PYTHONPATH=build/python /usr/bin/python3 tools/bench/python_overhead.py [N]
"""
import statistics
import sys
import time

import numpy as np

import frix


def run(n, warm):
    W = np.diag([2.0, 1.0, 1.0])
    q = np.array([-1.0, 0.2, 0.1])
    problem = frix.Problem(W, q, np.array([0.5]))
    zero = np.zeros(3)
    library = 0.0
    with frix.Solver(problem, solver="nsgs", tol=1e-8) as solver:
        solver.solve()
        start = time.perf_counter()
        for _ in range(n):
            res = solver.solve() if warm else solver.solve(r0=zero)
            library += res.time
        wall = time.perf_counter() - start
    return wall / n, library / n, res.iterations


def main():
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100000
    print(f"frix {frix.version()}, {n} solves of a one-contact problem through frix.Solver, medians of 5 runs")
    for warm, what in ((False, "from r0 = 0"), (True, "warm (from the last r)")):
        runs = [run(n, warm) for _ in range(5)]
        wall = statistics.median(r[0] for r in runs)
        lib = statistics.median(r[1] for r in runs)
        print(f"  {what}: {runs[0][2]} iterations; per solve {wall * 1e6:.2f} us in Python, "
              f"{lib * 1e6:.2f} us in the library: {(wall - lib) * 1e6:.2f} us above the C call")


if __name__ == "__main__":
    main()
