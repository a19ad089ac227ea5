"""Ctrl-C (SIGINT) stops a solve within 0.2 s with KeyboardInterrupt, in every solver, with and
without a progress callback, for frix.solve and a persistent frix.Solver.

Each case runs in a child interpreter (the signal must reach the main thread of a process that
is in the library): the child builds a problem, says it starts and solves to tol 1e-300 without
an iteration limit; the parent sends SIGINT a second later. The child prints the monotonic
clock (shared by the processes) where KeyboardInterrupt reached it, so the latency is measured
from the kill to the exception, scheduling included.
"""
import os
import signal
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import frix

# The wanted latency is 0.2 s (met on a quiet machine: notes/2026-11-28-trust.md); the
# assertion leaves room for the scheduling of two processes and a factorisation in progress on
# a machine running the suite two tests at a time (gnsn-al once took 1.4 s there), and every
# measured figure is printed (pytest -s shows them). Before, a solve ignored Ctrl-C.
LATENCY_GOAL = 0.2
LATENCY_ASSERTED = 3.0

CHILD = textwrap.dedent("""
    import sys, time
    import numpy as np
    import scipy.sparse as sp
    import frix

    def grid_problem(nc):
        # nc contacts between the neighbours of a grid of points: W = H^T H + 1e-3 I, sparse
        # and banded (cheap factorisations), q pressing the points together.
        rng = np.random.default_rng(1)
        side = int(np.ceil(np.sqrt(nc / 2))) + 1
        pairs = [(a, a + d) for a in range(side * side) for d in (1, side)
                 if (d == 1 and (a + 1) % side) or (d == side and a + side < side * side)][:nc]
        rows = np.array([[3 * i + k, 3 * j + k] for i, j in pairs for k in range(3)]).ravel()
        cols = np.repeat(np.arange(3 * nc), 2)
        vals = np.tile([1.0, -1.0], 3 * nc)
        H = sp.csc_matrix((vals, (rows, cols)), shape=(3 * side * side, 3 * nc))
        W = (H.T @ H + 1e-3 * sp.identity(3 * nc)).tocsc()
        q = rng.standard_normal(3 * nc)
        q[0::3] = -np.abs(q[0::3])
        if kind == "local":
            return frix.Problem(W, q, np.full(nc, 0.3))
        # The same contacts between unit point masses: M = I, u = H^T v + q.
        return frix.Problem.from_global(sp.identity(H.shape[0], format="csc"), H,
                                        np.zeros(H.shape[0]), q, np.full(nc, 0.3))

    solver, nc, kind, how = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
    with_callback = sys.argv[5] == "1"
    p = grid_problem(nc)
    calls = []
    callback = (lambda it, err, el: calls.append(it) and False) if with_callback else None
    opts = dict(solver=solver, tol=1e-300, max_iter=10**9, callback=callback)
    try:
        if how == "solver":
            s = frix.Solver(p, **opts)
            print("start", flush=True)
            res = s.solve()
        else:
            print("start", flush=True)
            res = frix.solve(p, check_existence=False, **opts)
        print("returned", res.status.name, time.monotonic(), flush=True)
    except KeyboardInterrupt:
        print("interrupted", time.monotonic(), len(calls), flush=True)
""")


def _kind(solver):
    """'global' for the solvers of global problems only, else 'local'."""
    try:
        frix.solve(frix.Problem(np.eye(3), [-1.0, 0.0, 0.0], [0.3]), solver=solver, max_iter=1,
                   check_existence=False)
    except frix.UnsupportedError:
        return "global"
    return "local"


def _interrupt_latency(solver, nc, how, with_callback, after=1.0):
    child = subprocess.Popen([sys.executable, "-c", CHILD, str(solver), str(nc), _kind(solver), how,
                              "1" if with_callback else "0"],
                             stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert child.stdout.readline().strip() == "start", child.stderr.read()
        time.sleep(after)
        sent = time.monotonic()
        child.send_signal(signal.SIGINT)
        out, err = child.communicate(timeout=15)
    finally:
        if child.poll() is None:
            child.kill()
            child.wait()
    words = out.split()
    assert words and words[0] == "interrupted", (out, err)
    assert "Exception ignored" not in err, err
    return float(words[1]) - sent


def _check_latency(what, latency):
    print(f"Ctrl-C latency, {what}: {latency:.3f} s (goal {LATENCY_GOAL} s)")
    assert latency < LATENCY_ASSERTED, (what, latency)


@pytest.mark.parametrize("solver", ["nsgs", "auto", "admm", "ipm"])
@pytest.mark.parametrize("with_callback", [False, True])
def test_ctrl_c_stops_frix_solve(solver, with_callback):
    latency = _interrupt_latency(solver, 3000, "solve", with_callback)
    _check_latency(f"frix.solve {solver}, 3000 contacts, callback {with_callback}", latency)


# The solvers of three-component problems (the child's problem); rolling-nsgs and rolling-nsn
# take rolling problems only.
@pytest.mark.parametrize("solver", [s.name for s in frix.solvers() if not s.name.startswith("rolling-")])
def test_ctrl_c_stops_every_solver(solver):
    latency = _interrupt_latency(solver, 3000, "solve", False, after=0.5)
    _check_latency(f"frix.solve {solver}, 3000 contacts", latency)


@pytest.mark.parametrize("with_callback", [False, True])
def test_ctrl_c_stops_a_persistent_solver(with_callback):
    latency = _interrupt_latency("nsgs", 3000, "solver", with_callback)
    _check_latency(f"Solver.solve nsgs, 3000 contacts, callback {with_callback}", latency)


def _small_problem():
    return frix.Problem(np.diag([1.0, 2.0, 2.0, 1.0, 2.0, 2.0]) + 0.1,
                        [-1.0, 0.3, -0.2, -0.5, -0.1, 0.4], [0.3, 0.5])


def test_outside_solves_ctrl_c_is_pythons_and_other_handlers_stay():
    p = _small_problem()
    frix.solve(p)  # (the first solve on the main thread sets frix's handler)
    with pytest.raises(KeyboardInterrupt):
        os.kill(os.getpid(), signal.SIGINT)
        time.sleep(1.0)  # (the handler runs at the next bytecode)
    caught = []

    def mine(signum, frame):
        caught.append(signum)

    previous = signal.signal(signal.SIGINT, mine)
    try:
        frix.solve(p)
        assert signal.getsignal(signal.SIGINT) is mine and not caught
    finally:
        signal.signal(signal.SIGINT, previous)


def test_a_keyboard_interrupt_of_the_callback_is_raised_not_a_status():
    def interrupted(iteration, error, elapsed):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        frix.solve(_small_problem(), solver="nsgs", tol=1e-300, callback=interrupted)
