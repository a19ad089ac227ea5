#!/usr/bin/python3
"""A FEM host's load steps on a global problem file: one frix.solve from r = 0 (the one-shot),
then a frix.Solver (persistent: M's factorisation and W kept) solved STEPS times, both with
SOLVER (auto by default), f scaled by 1 + 0.01 k at step k and each step warm-started from the
last answer. One line a solve: status, iterations, error, wall and CPU seconds, auto's stages
(solver, iterations, seconds) and the persistent solve's setup time.

    PYTHONPATH=build/python /usr/bin/python3 tools/bench/fem_file_steps.py FILE.hdf5
        [--solver NAME] [--tol T] [--steps S] [--save-r PREFIX] [--set KEY=VALUE ...]

To compare two builds, alternate runs of each (one at a time) and take medians:
    for i in 1 2 3; do for b in build-base build; do
        PYTHONPATH=$b/python /usr/bin/python3 tools/bench/fem_file_steps.py FILE.hdf5; done; done
--save-r writes each answer's r to PREFIX-oneshot.npy and PREFIX-stepK.npy; --set passes an
option to both (a number by its text, else a name: --set secant_start=0, --set shuffle=once).
"""
import argparse
import time

import numpy as np

import frix


def stages(res):
    return [(s.solver, s.iterations, round(s.seconds, 4)) for s in res.stages if s.solver]


def line(name, res, wall, cpu, extra=""):
    print(f"{name} {res.status.name} {res.iterations} {res.error:.3e} wall {wall:.3f} cpu {cpu:.3f} "
          f"{stages(res)}{extra}", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("file")
    ap.add_argument("--solver", default="auto")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--steps", type=int, default=5)
    ap.add_argument("--save-r", default=None)
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    a = ap.parse_args()
    extra = {}
    for kv in a.set:
        key, value = kv.split("=", 1)
        for kind in (int, float, str):  # a number by its text, else a choice's name
            try:
                extra[key] = kind(value)
                break
            except ValueError:
                pass
    p = frix.load(a.file)
    t, c = time.perf_counter(), time.process_time()
    res = frix.solve(p, solver=a.solver, tol=a.tol, threads=a.threads, **extra)
    line("oneshot", res, time.perf_counter() - t, time.process_time() - c)
    if a.save_r:
        np.save(f"{a.save_r}-oneshot.npy", np.array(res.r))
    solver = frix.Solver(p, solver=a.solver, tol=a.tol, threads=a.threads, **extra)
    f0 = np.array(p.f, copy=True)
    for k in range(a.steps):
        if k:
            solver.update(f=f0 * (1 + 0.01 * k))
        t, c = time.perf_counter(), time.process_time()
        res = solver.solve()
        line(f"step{k}", res, time.perf_counter() - t, time.process_time() - c,
             f" setup {res.times.get('setup', 0.0):.3f}")
        if a.save_r:
            np.save(f"{a.save_r}-step{k}.npy", np.array(res.r))


if __name__ == "__main__":
    main()
