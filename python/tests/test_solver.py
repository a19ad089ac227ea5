"""frix.Solver, the persistent solver: time steps, new values on W's structure, contacts that come
and go."""
import numpy as np
import pytest
import scipy.sparse as sp

import frix


def test_persistent_solver_time_steps(two_contacts):
    W, q, mu = two_contacts
    p = frix.Problem(sp.csr_matrix(W), q, mu)
    with frix.Solver(p, tol=1e-10) as s:
        first = s.solve()
        assert first.converged
        for step in range(3):
            q_step = q * (1.0 + 0.1 * step)
            s.update(q=q_step)
            res = s.solve()
            direct = frix.solve(frix.Problem(W, q_step, mu), tol=1e-10, r0=first.r)
            assert res.converged
            np.testing.assert_allclose(res.r, direct.r, atol=1e-8)
        s.update(W_values=sp.csr_matrix(W).data * 2.0)
        res = s.solve()
        np.testing.assert_allclose(res.u, 2.0 * W @ res.r + q_step, atol=1e-9)
        with pytest.raises(frix.InvalidArgumentError):
            p.close()  # the Solver still reads it
    p.close()


def test_w_values_on_the_structure_as_it_was_built(two_contacts):
    W, q, mu = two_contacts
    A = sp.csr_matrix(W)
    p = frix.Problem(A, q, mu)
    values = A.data.copy()
    A.data[:] = 0.0  # later changes to the caller's matrix do not move the structure
    with frix.Solver(p, tol=1e-10) as s:
        s.update(W_values=3.0 * values)
        res = s.solve()
        np.testing.assert_allclose(res.u, 3.0 * W @ res.r + q, atol=1e-9)
        with pytest.raises(frix.DimensionError):
            s.update(W_values=values[:-1])


def test_persistent_solver_contacts_come_and_go(two_contacts):
    W, q, mu = two_contacts
    one = frix.Problem(W[:3, :3], q[:3], mu[:1])
    with frix.Solver(frix.Problem(W, q, mu), tol=1e-10) as s:
        assert s.solve().converged
        s.set_contacts(mu[:1], W=W[:3, :3], q=q[:3])
        res = s.solve()
        assert res.converged and res.r.shape == (3,)
        np.testing.assert_allclose(res.r, frix.solve(one, tol=1e-10).r, atol=1e-8)
        with pytest.raises(frix.InvalidArgumentError):
            s.set_contacts(mu, H=sp.eye(6), w=q)  # a local problem's: W and q
        with pytest.raises(frix.DimensionError):
            s.set_contacts(mu, W=W[:3, :3], q=q)  # W for one contact, mu for two
        assert s.solve().r.shape == (3,)  # nothing of a refused call was taken
        s.set_contacts(mu, W=W, q=q)
        assert s.solve().converged
    # Global: the same bodies, the second contact only (H's last three columns).
    M = sp.identity(6, format="csc")
    H = sp.csc_matrix(np.linalg.cholesky(W))
    f = np.zeros(6)
    p = frix.Problem.from_global(M, H, f, q, mu)
    with frix.Solver(p, tol=1e-10) as s:
        s.set_contacts(mu[1:], H=H[:, 3:], w=q[3:])
        res = s.solve()
        direct = frix.solve(frix.Problem.from_global(M, H[:, 3:], f, q[3:], mu[1:]), tol=1e-10)
        assert res.converged and res.v.shape == (6,)
        np.testing.assert_allclose(res.r, direct.r, atol=1e-8)
