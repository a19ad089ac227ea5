"""Rolling friction: Problem(..., mu_r=...) in both forms, the measure on a contact solved by
hand, rolling-nsgs and auto, the persistent solver, files written and read back, and the
three-component solvers' refusal."""
import numpy as np
import pytest

import frix


def rolling_contact():
    """One contact, W = I: r* = (1, 0, 0, -0.01, 0) rolls (w_R = 0.04) without sliding."""
    return np.eye(5), np.array([-1.0, 0.0, 0.0, 0.05, 0.0]), np.array([0.5]), np.array([0.01])


def sphere_on_ground(mu=0.3, mu_r=0.02, radius=0.5, mass=2.0):
    """A sphere on the ground, pushed sideways and spun, under gravity: one step, global form."""
    inertia = 0.4 * mass * radius * radius
    M = np.diag([mass] * 3 + [inertia] * 3)
    t1, t2, n = np.eye(3)  # the ground's normal is z
    H = np.zeros((6, 5))
    for k, e in enumerate((n, t1, t2)):
        H[:3, k] = e
        H[3:, k] = radius * np.cross(e, n)
    H[3:, 3], H[3:, 4] = t1, t2
    v_free = np.array([0.3, 0.0, -0.1, 0.0, 2.0, 0.0])
    return M, H, M @ v_free, np.zeros(5), np.array([mu]), np.array([mu_r])


def test_local_problem_and_hand_solution():
    W, q, mu, mu_r = rolling_contact()
    p = frix.Problem(W, q, mu, mu_r=mu_r)
    assert p.rolling and p.kind == "local"
    assert p.contacts == 1 and p.contact_dofs == 5
    assert p.mu_r is mu_r  # borrowed
    res = frix.solve(p, solver="rolling-nsgs", tol=1e-12)
    assert res.converged
    np.testing.assert_allclose(res.r, [1, 0, 0, -0.01, 0], rtol=0, atol=1e-12)
    # The measure at r = 0: x = -q^ projects on the rolling cone alone (docs/rolling.md).
    m = p.measure(np.zeros(5))
    assert m["error_relative"] == pytest.approx(1 / np.sqrt(1.0001) / np.sqrt(1.0025), rel=1e-13)
    assert "rolling" in repr(p)


def test_classic_problem_is_not_rolling():
    p = frix.Problem(np.eye(3), np.array([-1.0, 0, 0]), np.array([0.3]))
    assert not p.rolling and p.mu_r is None


def test_global_problem_solved_by_auto():
    M, H, f, w, mu, mu_r = sphere_on_ground()
    p = frix.Problem.from_global(M, H, f, w, mu, mu_r=mu_r)
    assert p.rolling and p.kind == "global" and p.dofs == 6
    res = frix.solve(p, tol=1e-10)
    assert res.converged
    np.testing.assert_allclose(M @ res.v, H @ res.r + f, rtol=0, atol=1e-12)
    np.testing.assert_allclose(res.u, H.T @ res.v + w, rtol=0, atol=1e-12)
    assert res.r[0] > 0
    # The rolling moment resists the spin, within its cone.
    assert np.hypot(res.r[3], res.r[4]) <= mu_r[0] * res.r[0] * (1 + 1e-12)
    assert [s.solver for s in res.stages if s.solver] == ["rolling-nsgs"]


def test_solvers_by_siconos_name():
    W, q, mu, mu_r = rolling_contact()
    p = frix.Problem(W, q, mu, mu_r=mu_r)
    for name in ("ROLLING_FRICTION_3D_NSGS", "RFC3D_NSGS", 3000):
        assert frix.solve(p, solver=name, tol=1e-12).converged


def test_three_component_solvers_refuse():
    W, q, mu, mu_r = rolling_contact()
    p = frix.Problem(W, q, mu, mu_r=mu_r)
    for name in ("nsgs", "nsn-ac", "admm"):
        with pytest.raises(frix.UnsupportedError, match="rolling"):
            frix.solve(p, solver=name)
    # So does a persistent solver by one of them.
    with pytest.raises(frix.UnsupportedError, match="rolling"):
        frix.Solver(p, solver="nsgs")


def test_persistent_solver():
    """frix.Solver on a rolling problem: each solve is frix.solve's from the same start, through
    a new f, a new mu_r and a new set of contacts (none, then the sphere again)."""
    M, H, f, w, mu, mu_r = sphere_on_ground()
    p = frix.Problem.from_global(M, H, f, w, mu, mu_r=mu_r)
    s = frix.Solver(p, tol=1e-10)
    first = s.solve()
    np.testing.assert_array_equal(first.r, frix.solve(p, tol=1e-10).r)
    f2, mu_r2 = 1.1 * f, np.array([0.005])
    s.update(f=f2, mu_r=mu_r2)
    second = s.solve()
    expected = frix.solve(frix.Problem.from_global(M, H, f2, w, mu, mu_r=mu_r2), r0=first.r, tol=1e-10)
    np.testing.assert_array_equal(second.r, expected.r)
    assert second.iterations == expected.iterations
    assert np.hypot(second.r[3], second.r[4]) <= mu_r2[0] * second.r[0] * (1 + 1e-12)
    # No contact: the sphere flies (v = M^-1 f); then the contact again, with its mu_r.
    s.set_contacts(np.zeros(0), H=np.zeros((6, 0)), w=np.zeros(0), mu_r=np.zeros(0))
    np.testing.assert_allclose(s.solve().v, np.linalg.solve(M, f2), rtol=1e-14)
    s.set_contacts(mu, H=H, w=w, mu_r=mu_r)
    np.testing.assert_array_equal(s.solve().r, frix.solve(frix.Problem.from_global(M, H, f2, w, mu, mu_r=mu_r),
                                                          tol=1e-10).r)
    # Bad input: a negative mu_r, a mu_r missing or given to a problem without rolling friction.
    with pytest.raises(frix.InvalidArgumentError, match="mu_r"):
        s.update(mu_r=np.array([-1.0]))
    with pytest.raises(frix.InvalidArgumentError, match="mu_r"):
        s.set_contacts(mu, H=H, w=w)
    plain = frix.Solver(frix.Problem(np.eye(3), np.array([-1.0, 0, 0]), np.array([0.3])))
    with pytest.raises(frix.InvalidArgumentError, match="rolling"):
        plain.update(mu_r=np.array([0.01]))


def test_bad_input():
    W, q, mu, mu_r = rolling_contact()
    with pytest.raises(frix.DimensionError):
        frix.Problem(W, q, mu, mu_r=np.array([0.01, 0.01]))
    with pytest.raises(frix.InvalidArgumentError, match="mu_r"):
        frix.Problem(W, q, mu, mu_r=np.array([-0.01]))
    with pytest.raises(frix.DimensionError):
        frix.Problem(np.eye(3), q[:3], mu, mu_r=mu_r)


def test_file_round_trip(tmp_path):
    for p in (frix.Problem(*rolling_contact()[:3], mu_r=rolling_contact()[3]),
              frix.Problem.from_global(*sphere_on_ground()[:5], mu_r=sphere_on_ground()[5])):
        res = frix.solve(p, tol=1e-12)
        path = tmp_path / f"{p.kind}.hdf5"
        p.save(path, solution=res)
        back = frix.load(path)
        assert back.rolling and back.kind == p.kind
        np.testing.assert_array_equal(back.mu_r, p.mu_r)
        r, u, v = frix.load_solution(path, back)
        np.testing.assert_array_equal(r, res.r)
        np.testing.assert_array_equal(u, res.u)
        assert frix.solve(back, tol=1e-12).converged
