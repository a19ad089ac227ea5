"""frix.solve: the result's fields, a global problem, the progress callback, and the existence
check."""
import numpy as np
import pytest

import frix


def test_result_fields(two_contacts):
    W, q, mu = two_contacts
    res = frix.solve(frix.Problem(W, q, mu), tol=1e-10)
    assert res.status == frix.Status.CONVERGED and res.converged and str(res.status) == "converged"
    assert res.solver == "auto" and res.iterations > 0 and res.error <= 1e-10 and res.time >= 0
    assert res.r.shape == (6,) and res.u.shape == (6,) and res.v is None
    np.testing.assert_allclose(res.u, W @ res.r + q, atol=1e-12)
    assert set(res.measures) >= {"error_relative", "cone_violation", "penetration"}
    assert res.stages and any(s.solver for s in res.stages)
    assert res.existence == frix.Existence.NOT_CHECKED


def test_global_problem(fclib):
    p = frix.load(fclib / "global" / "Box_Stacks-i0035-31-0.hdf5")
    assert p.kind == "global" and p.dofs > 0
    res = frix.solve(p, tol=1e-8)
    assert res.converged and res.v.shape == (p.dofs,)
    # The times of the setup (auto reduces to W here), of it W's, within the whole solve.
    t = res.times
    assert 0.0 < t["reduction"] < t["setup"] <= res.time
    assert frix.solve(p, solver="gnsn-ac", tol=1e-8).times["reduction"] == 0.0
    # The same problem rebuilt from its own arrays.
    again = frix.Problem.from_global(p.M, p.H, np.array(p.f), np.array(p.w), np.array(p.mu))
    np.testing.assert_allclose(frix.solve(again, tol=1e-8).r, res.r, atol=1e-12)


def test_callback_sees_progress_and_stops_the_solve(two_contacts):
    p = frix.Problem(*two_contacts)
    seen = []

    def stop_at_third(iteration, error, elapsed):
        seen.append((iteration, error, elapsed))
        return iteration >= 3

    res = frix.solve(p, solver="nsgs", tol=1e-300, max_iter=1000, callback=stop_at_third,
                     check_existence=False)
    assert res.status == frix.Status.STOPPED_BY_CALLBACK and len(seen) == 3

    def fails(iteration, error, elapsed):
        raise RuntimeError("from the callback")

    with pytest.raises(RuntimeError, match="from the callback"):
        frix.solve(p, solver="nsgs", tol=1e-300, max_iter=1000, callback=fails)


def test_no_existence_check_after_a_callback_stop(two_contacts):
    p = frix.Problem(*two_contacts)
    res = frix.solve(p, solver="nsgs", tol=1e-300, callback=lambda *a: True)
    assert res.status == frix.Status.STOPPED_BY_CALLBACK
    assert res.existence == frix.Existence.NOT_CHECKED
    res = frix.solve(p, solver="nsgs", tol=1e-300, max_iter=3)
    assert res.status == frix.Status.MAX_ITER and res.existence != frix.Existence.NOT_CHECKED


def test_the_existence_check_is_the_librarys_option(two_contacts):
    """check_existence is the option existence_check, which decides when given too; frix_solve
    and frix_persistent_solve run the check of a failed run (a verdict and its margin)."""
    p = frix.Problem(*two_contacts)
    failing = dict(solver="nsgs", tol=1e-300, max_iter=3)
    checked = frix.solve(p, **failing)
    assert checked.existence == frix.Existence.GUARANTEED and checked.existence_margin > 0
    assert frix.solve(p, check_existence=False, **failing).existence == frix.Existence.NOT_CHECKED
    assert frix.solve(p, existence_check=0, **failing).existence == frix.Existence.NOT_CHECKED
    assert (frix.solve(p, check_existence=False, existence_check=1, **failing).existence
            == frix.Existence.GUARANTEED)
    with frix.Solver(p, **failing) as s:
        assert s.solve().existence == frix.Existence.GUARANTEED
    with frix.Solver(p, existence_check=0, **failing) as s:
        assert s.solve().existence == frix.Existence.NOT_CHECKED
