"""Options: by name, validated by the library, integers range-checked before their conversion
to int64_t, choices by name, and the solvers listed."""
import numpy as np
import pytest

import frix


def test_options_by_name_validated_by_the_library(two_contacts):
    W, q, mu = two_contacts
    p = frix.Problem(W, q, mu)
    res = frix.solve(p, solver="admm", tol=1e-9, rho=0.5, acceleration=0)
    assert res.converged and res.solver == "admm"
    with pytest.raises(frix.UnknownOptionError) as e:
        frix.solve(p, solver="nsgs", rho=0.5)  # nsgs has no rho
    assert e.value.code == -8 and "rho" in str(e.value)
    with pytest.raises(frix.OptionRangeError):
        frix.solve(p, tol=-1.0)
    with pytest.raises(frix.OptionRangeError):
        frix.solve(p, solver="nsgs", max_iter=2.5)
    with pytest.raises(frix.UnknownSolverError):
        frix.solve(p, solver="no-such-solver")
    # Siconos's spelling and ids are accepted.
    assert frix.solve(p, solver="FRICTION_3D_NSGS", tol=1e-9).solver == "nsgs"
    assert frix.solve(p, solver=500, tol=1e-9).solver == "nsgs"


def test_integer_options_range_checked_before_conversion(two_contacts):
    p = frix.Problem(*two_contacts)
    for bad in (2**64 + 5, 2**63, -(2**63) - 1, 10**30):
        with pytest.raises(frix.OptionRangeError) as e:
            frix.solve(p, solver="nsgs", max_iter=bad)
        assert "max_iter" in str(e.value) and str(bad) in str(e.value)
        assert "1000000000" in str(e.value)  # the bound, as an integer
    with pytest.raises(frix.OptionRangeError):
        frix.Solver(p, solver="nsgs", max_iter=2**64 + 5)
    with pytest.raises(frix.OptionRangeError):
        frix.solve(p, solver="nsgs", tol=10**400)  # beyond the doubles
    # In range they still work, as floats with integral values too.
    assert frix.solve(p, solver="nsgs", max_iter=7.0, tol=1e-300,
                      check_existence=False).iterations == 7


def test_choice_options_by_name(two_contacts):
    p = frix.Problem(*two_contacts)
    named = frix.solve(p, solver="nsgs", tol=1e-300, max_iter=5, shuffle="each_sweep", seed=3,
                       check_existence=False)
    numbered = frix.solve(p, solver="nsgs", tol=1e-300, max_iter=5, shuffle=2, seed=3,
                          check_existence=False)
    assert np.array_equal(named.r, numbered.r)
    assert frix.solve(p, solver="nsgs", error_measure="siconos", local_solver="newton_ac",
                      tol=1e-10).converged
    assert frix.solve(p, solver="nsn-ac", rho_strategy="split", line_search="armijo",
                      hybrid="none", tol=1e-10).converged
    assert frix.solve(p, solver="prox", inner_solver="nsn-fb", tol=1e-10).converged
    res = frix.solve(p, solver="nsgs", error_measure="q_relative", tol=1e-10)
    assert res.converged and res.error == pytest.approx(res.measures["error_q_relative"])
    with pytest.raises(frix.OptionRangeError) as e:
        frix.solve(p, solver="nsgs", shuffle="sometimes")
    assert all(n in str(e.value) for n in ("none", "once", "each_sweep"))
    with frix.Solver(p, solver="nsgs", shuffle="once", tol=1e-10) as s:
        assert s.solve().converged


def test_bool_options_and_warned_copies(two_contacts):
    W, q, mu = two_contacts
    assert frix.solve(frix.Problem(W, q, mu), solver="admm", tol=1e-9, acceleration=False).converged
    Q = np.stack([q, q], axis=1)  # q as a column of a 2-D array: not contiguous
    with pytest.warns(frix.ConversionWarning):
        p = frix.Problem(W, Q[:, 0], mu)
    assert not np.shares_memory(p.q, Q)


def test_solvers_listed():
    names = {s.name for s in frix.solvers()}
    assert {"auto", "nsgs", "admm", "ipm"} <= names
    assert all(s.description for s in frix.solvers())
