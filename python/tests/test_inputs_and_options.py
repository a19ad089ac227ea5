"""Options and inputs checked in Python before they reach C: integers range-checked before
their conversion to int64_t, NUL characters refused in C strings, errors naming the argument
at fault, no ConversionWarning for empty arrays, and choice options by name."""
import warnings

import numpy as np
import pytest

import frix


def two_contacts():
    """Two coupled contacts pressed into the ground (as test_frix.py's)."""
    rng = np.random.default_rng(7)
    A = rng.standard_normal((6, 6))
    W = A @ A.T + 6.0 * np.eye(6)
    q = np.array([-1.0, 0.3, -0.2, -0.5, -0.1, 0.4])
    return W, q, np.array([0.3, 0.5])


def test_integer_options_range_checked_before_conversion():
    p = frix.Problem(*two_contacts())
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


def test_nul_characters_refused(tmp_path):
    p = frix.Problem(*two_contacts())
    for call in (lambda: frix.load(str(tmp_path / "a.hdf5") + "\0.dat"),
                 lambda: p.save(str(tmp_path / "b.hdf5") + "\0x"),
                 lambda: frix.solve(p, solver="nsgs\0ipm"),
                 lambda: frix.solve(p, solver="nsgs", shuffle="once\0"),
                 lambda: setattr(p, "title", "a\0b")):
        with pytest.raises(frix.InvalidArgumentError, match="NUL"):
            call()
    assert not (tmp_path / "b.hdf5").exists()


def test_errors_name_the_argument_at_fault():
    W, q, mu = two_contacts()
    with pytest.raises(frix.DimensionError, match="mu has 3 entries, expected 2"):
        frix.Problem(W, q, np.array([0.3, 0.5, 0.1]))
    with pytest.raises(frix.DimensionError, match="mu has 1 entries, expected 2"):
        frix.Problem(W, q, np.array([0.3]))
    with pytest.raises(frix.DimensionError, match="q has 5 entries, expected 6"):
        frix.Problem(W, q[:5], mu)
    M, H = np.eye(4), np.ones((4, 6))
    with pytest.raises(frix.DimensionError, match="mu has 3 entries, expected 2"):
        frix.Problem.from_global(M, H, np.zeros(4), np.zeros(6), np.ones(3))
    with pytest.raises(frix.DimensionError, match="w has 3 entries, expected 6"):
        frix.Problem.from_global(M, H, np.zeros(4), np.zeros(3), np.ones(2))


def test_no_conversion_warning_for_empty_arrays():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = frix.Problem(np.zeros((0, 0)), np.zeros(0), np.zeros(0))  # a contact-free step
        res = frix.solve(p)
        assert res.converged and res.r.shape == (0,)
        g = frix.Problem.from_global(np.eye(2), np.zeros((2, 0)), np.ones(2), np.zeros(0),
                                     np.zeros(0))
        assert frix.solve(g).converged


def test_choice_options_by_name():
    p = frix.Problem(*two_contacts())
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
