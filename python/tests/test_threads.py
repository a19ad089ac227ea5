"""Threads: solves at once with the same answers, the GIL released while the library solves, and
problems and Solvers in use that refuse to close or be re-entered."""
import threading
import time

import numpy as np
import pytest

import frix


def test_threads_solve_at_once_with_the_same_answers(fclib):
    p = frix.load(fclib / "local" / "Capsules-i125-1213.hdf5")
    reference = frix.solve(p, tol=1e-8).r
    results, errors = [None] * 4, []

    def work(k):
        try:
            results[k] = frix.solve(p, tol=1e-8).r
        except Exception as e:  # noqa: BLE001
            errors.append(e)

    threads = [threading.Thread(target=work, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for r in results:
        np.testing.assert_array_equal(r, reference)


def test_the_gil_is_released_while_the_library_solves(fclib):
    """The main thread keeps running Python while another thread's solve is in the library."""
    p = frix.load(fclib / "local" / "Capsules-i125-1213.hdf5")
    window = {}

    def work():
        window["start"] = time.perf_counter()
        frix.solve(p, solver="nsgs", tol=1e-300, max_iter=20000, check_existence=False)
        window["end"] = time.perf_counter()

    t = threading.Thread(target=work)
    ticks = []
    t.start()
    while t.is_alive():
        ticks.append(time.perf_counter())
    t.join()
    # The middle half of the solve is inside the library's frix_solve (its Python set-up and
    # result take microseconds); held there, the GIL would stop the main thread all along it.
    start, end = window["start"], window["end"]
    quarter = (end - start) / 4
    inside = sum(1 for x in ticks if start + quarter < x < end - quarter)
    assert end - start > 0.04 and inside > 1000, (end - start, inside)


def test_in_use_problems_and_solvers_refuse_to_close_or_reenter(two_contacts):
    """A problem is not freed under a running solve, nor a Solver called from its callback."""
    p = frix.Problem(*two_contacts)
    started, tried = threading.Event(), threading.Event()

    def hold(iteration, error, elapsed):
        started.set()
        tried.wait(10)
        return True

    t = threading.Thread(target=lambda: frix.solve(p, solver="nsgs", tol=1e-300, callback=hold))
    t.start()
    assert started.wait(10)
    with pytest.raises(frix.InvalidArgumentError, match="in use"):
        p.close()
    tried.set()
    t.join()
    s = frix.Solver(p, solver="nsgs", tol=1e-300, max_iter=5, callback=lambda *a: s.solve())
    with pytest.raises(frix.InvalidArgumentError, match="own callback"):
        s.solve()
    with pytest.raises(frix.InvalidArgumentError, match="in use"):
        p.close()
    s.close()
    s.close()  # (twice is harmless)
    with pytest.raises(frix.InvalidArgumentError, match="closed"):
        s.solve()
    p.close()
