"""Spinning friction (six entries a contact): Problem(..., mu_r=..., mu_s=...) in both forms,
its validation, the measure of a contact checked by hand, files written and read back, and the
persistent solver's calls. (Solving is tested with the rolling solvers that take six entries.)"""
import numpy as np
import pytest

import frix


def spinning_contact():
    """One contact, W = I: r* = (1, 0, 0, 0, 0, -0.02) spins (w_S = 0.03) against mu_s r_N,
    neither sliding nor rolling; u^_N = mu_s |w_S| makes r* . u^ = 0."""
    return (np.eye(6), np.array([-1.0, 0.0, 0.0, 0.0, 0.0, 0.05]), np.array([0.5]), np.array([0.01]),
            np.array([0.02]))


def two_contacts_global():
    """Two contacts on a body of 6 dofs (M = 2 I), H of 6 x 12 with distinct entries."""
    M = 2.0 * np.eye(6)
    H = np.arange(72, dtype=float).reshape(6, 12) / 71.0 - 0.5
    return M, H, np.linspace(-1, 1, 6), np.linspace(0, 0.1, 12), np.array([0.3, 0.4]), \
        np.array([0.01, 0.02]), np.array([0.003, 0.004])


def test_local_problem_and_measure_by_hand():
    W, q, mu, mu_r, mu_s = spinning_contact()
    p = frix.Problem(W, q, mu, mu_r=mu_r, mu_s=mu_s)
    assert p.rolling and p.spinning and p.kind == "local"
    assert p.contacts == 1 and p.contact_dofs == 6
    assert p.mu_s is mu_s and p.mu_r is mu_r  # borrowed
    m = p.measure(np.array([1.0, 0, 0, 0, 0, -0.02]))
    assert m["error_relative"] <= 1e-15
    # At r = 0, x = -q^ = (0.999, 0, 0, 0, 0, -0.05) is cut on the spinning interval alone:
    # the residual is 1 / sqrt(1 + mu_s^2) (tests/test_spinning.c).
    assert p.measure(np.zeros(6))["residual_absolute"] == pytest.approx(1 / np.sqrt(1.0004), rel=1e-13)
    # Off the spinning cone, not a solution.
    assert p.measure(np.array([1.0, 0, 0, 0, 0, -0.5]))["cone_violation"] > 0.4
    assert "spinning" in repr(p)


def test_problems_without_spinning():
    W, q, mu, mu_r, _ = spinning_contact()
    rolling = frix.Problem(W[:5, :5], q[:5], mu, mu_r=mu_r)
    assert rolling.rolling and not rolling.spinning and rolling.mu_s is None
    plain = frix.Problem(np.eye(3), q[:3], mu)
    assert not plain.spinning and plain.mu_s is None


def test_global_problem():
    M, H, f, w, mu, mu_r, mu_s = two_contacts_global()
    p = frix.Problem.from_global(M, H, f, w, mu, mu_r=mu_r, mu_s=mu_s)
    assert p.spinning and p.kind == "global" and p.contact_dofs == 12 and p.dofs == 6
    np.testing.assert_array_equal(p.mu_s, mu_s)
    # The measure's equilibrium: v = M^-1 (H r + f) balances any r.
    r = np.zeros(12)
    r[0], r[6] = 1.0, 2.0
    assert p.measure(r, np.linalg.solve(M, H @ r + f))["equilibrium"] <= 1e-15


def test_bad_input():
    W, q, mu, mu_r, mu_s = spinning_contact()
    with pytest.raises(frix.InvalidArgumentError, match="mu_s"):
        frix.Problem(W, q, mu, mu_r=mu_r, mu_s=np.array([-0.01]))
    with pytest.raises(frix.NotFiniteError):
        frix.Problem(W, q, mu, mu_r=mu_r, mu_s=np.array([np.nan]))
    with pytest.raises(frix.DimensionError):
        frix.Problem(W, q, mu, mu_r=mu_r, mu_s=np.array([0.01, 0.01]))
    # Six entries a contact: a 5 x 5 W is no contact of this law, nor is a 6-entry q with mu_r only.
    with pytest.raises(frix.DimensionError):
        frix.Problem(W[:5, :5], q[:5], mu, mu_r=mu_r, mu_s=mu_s)
    with pytest.raises(frix.DimensionError):
        frix.Problem(W, q, mu, mu_r=mu_r)
    # Spinning friction comes with rolling friction.
    with pytest.raises(frix.InvalidArgumentError, match="needs mu_r"):
        frix.Problem(W, q, mu, mu_s=mu_s)
    M, H, f, w, mu2, mu_r2, mu_s2 = two_contacts_global()
    with pytest.raises(frix.InvalidArgumentError, match="needs mu_r"):
        frix.Problem.from_global(M, H, f, w, mu2, mu_s=mu_s2)
    with pytest.raises(frix.DimensionError):
        frix.Problem.from_global(M, H[:, :10], f, w[:10], mu2, mu_r=mu_r2, mu_s=mu_s2)


def test_file_round_trip(tmp_path):
    W, q, mu, mu_r, mu_s = spinning_contact()
    M, H, f, w, mu2, mu_r2, mu_s2 = two_contacts_global()
    for p in (frix.Problem(W, q, mu, mu_r=mu_r, mu_s=mu_s),
              frix.Problem.from_global(M, H, f, w, mu2, mu_r=mu_r2, mu_s=mu_s2)):
        m, n = p.contact_dofs, p.dofs
        solution = type("Answer", (), {"r": np.linspace(0, 1, m), "u": np.linspace(1, 2, m),
                                       "v": np.linspace(2, 3, n) if n else None})
        for compression in (True, False):
            path = tmp_path / f"{p.kind}-{compression}.hdf5"
            p.save(path, solution=solution, title="spinning", compression=compression)
            back = frix.load(path)
            assert back.spinning and back.kind == p.kind and back.title == "spinning"
            np.testing.assert_array_equal(back.mu_s, p.mu_s)
            np.testing.assert_array_equal(back.mu_r, p.mu_r)
            np.testing.assert_array_equal(back.mu, p.mu)
            if p.kind == "local":
                np.testing.assert_array_equal(back.q, p.q)
                np.testing.assert_array_equal(back.W.toarray(), W)
            else:
                np.testing.assert_array_equal(back.w, p.w)
                np.testing.assert_array_equal(back.f, p.f)
                np.testing.assert_array_equal(back.H.toarray(), H)
            r, u, v = frix.load_solution(path, back)
            np.testing.assert_array_equal(r, solution.r)
            np.testing.assert_array_equal(u, solution.u)
            if n:
                np.testing.assert_array_equal(v, solution.v)


def test_persistent_calls():
    """frix.Solver takes a problem with spinning friction: mu_s in update and set_contacts, and
    the rolling calls' form refused."""
    W, q, mu, mu_r, mu_s = spinning_contact()
    p = frix.Problem(W, q, mu, mu_r=mu_r, mu_s=mu_s)
    s = frix.Solver(p)
    s.update(q=q, mu_r=mu_r, mu_s=np.array([0.01]))
    with pytest.raises(frix.InvalidArgumentError, match=r"mu_s\[0\]"):
        s.update(mu_s=np.array([-1.0]))
    W2, q2 = np.eye(12), np.concatenate([q, q])
    s.set_contacts(np.array([0.3, 0.3]), W=W2, q=q2, mu_r=np.array([0.01, 0.01]), mu_s=np.array([0.0, 0.1]))
    with pytest.raises(frix.InvalidArgumentError, match="mu_s"):
        s.set_contacts(mu, W=W, q=q, mu_r=mu_r)
    with pytest.raises(frix.DimensionError):
        s.set_contacts(mu, W=W[:5, :5], q=q[:5], mu_r=mu_r, mu_s=mu_s)
    s.close()
    rolling = frix.Solver(frix.Problem(W[:5, :5], q[:5], mu, mu_r=mu_r))
    with pytest.raises(frix.InvalidArgumentError, match="spinning"):
        rolling.update(mu_s=mu_s)
    with pytest.raises(frix.InvalidArgumentError, match="mu_r"):
        rolling.set_contacts(mu, W=W[:5, :5], q=q[:5], mu_r=mu_r, mu_s=mu_s)
    rolling.close()
