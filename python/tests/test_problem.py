"""Problems: every input format, vectors borrowed or converted, FCLIB files (their info texts
and compression), measures of a given answer, and handles that are not copied."""
import warnings

import numpy as np
import pytest
import scipy.sparse as sp

import frix


def test_every_input_format_gives_the_same_r(two_contacts):
    W, q, mu = two_contacts
    reference = frix.solve(frix.Problem(W, q, mu), solver="nsgs", tol=1e-12).r
    inputs = [np.asfortranarray(W)]
    for fmt in ("csr", "csc", "coo", "bsr"):
        inputs.append(sp.csr_matrix(W).asformat(fmt))
        inputs.append(sp.csr_array(W).asformat(fmt))
    inputs.append(sp.dia_matrix(W))
    for A in inputs:
        res = frix.solve(frix.Problem(A, q, mu), solver="nsgs", tol=1e-12)
        assert res.converged, type(A)
        np.testing.assert_allclose(res.r, reference, rtol=0, atol=1e-12, err_msg=str(type(A)))


def test_vectors_borrowed_without_copy_and_converted_with_a_warning(two_contacts):
    W, q, mu = two_contacts
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # float64 contiguous: no conversion, no warning
        p = frix.Problem(sp.csr_matrix(W), q, mu)
    assert p.q is q and p.mu is mu
    assert np.shares_memory(p.q, q)
    # Changed in place, the problem sees the new q at the next solve.
    before = frix.solve(p, solver="nsgs", tol=1e-12).r.copy()
    q[0] = -2.0
    after = frix.solve(p, solver="nsgs", tol=1e-12).r
    assert not np.allclose(before, after)
    # Other dtypes are converted once, with a warning.
    with pytest.warns(frix.ConversionWarning):
        p32 = frix.Problem(W, q.astype(np.float32), mu)
    assert p32.q.dtype == np.float64 and not np.shares_memory(p32.q, q)
    # Index arrays of int32 give the same problem.
    A32 = sp.csr_matrix(W)
    A32.indices = A32.indices.astype(np.int32)
    A32.indptr = A32.indptr.astype(np.int32)
    np.testing.assert_array_equal(frix.Problem(A32, q, mu).W.toarray(), frix.Problem(W, q, mu).W.toarray())


def test_no_conversion_warning_for_empty_arrays():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = frix.Problem(np.zeros((0, 0)), np.zeros(0), np.zeros(0))  # a contact-free step
        res = frix.solve(p)
        assert res.converged and res.r.shape == (0,)
        g = frix.Problem.from_global(np.eye(2), np.zeros((2, 0)), np.ones(2), np.zeros(0),
                                     np.zeros(0))
        assert frix.solve(g).converged


def test_fclib_round_trip(tmp_path, fclib):
    p = frix.load(fclib / "converted" / "Confeti-ex03-Fc3D-SBM.from_dat.hdf5")
    res = frix.solve(p, tol=1e-10)
    out = tmp_path / "confeti.hdf5"
    p.save(out, solution=res)
    back = frix.load(out)
    assert back.contacts == p.contacts and back.kind == "local"
    np.testing.assert_array_equal(back.q, p.q)
    np.testing.assert_array_equal(back.mu, p.mu)
    assert (back.W != p.W).nnz == 0
    np.testing.assert_array_equal(frix.solve(back, tol=1e-10).r, res.r)


def test_handles_are_not_copied(two_contacts):
    import copy
    import pickle
    p = frix.Problem(*two_contacts)
    res = frix.solve(p)
    for obj in (p, res, frix.Solver(p)):
        with pytest.raises(TypeError):
            copy.copy(obj)
        with pytest.raises(TypeError):
            pickle.dumps(obj)


def test_measure_a_given_r_as_a_solve_does(two_contacts):
    # frix_problem_measure through Problem.measure: the measures of a result's own r and v are
    # the result's; a bad r is refused; v is required for a global problem, refused for a local.
    def same(a, b):  # equal, NaN (a local problem's equilibrium) included
        return a.keys() == b.keys() and all(a[k] == b[k] or (np.isnan(a[k]) and np.isnan(b[k])) for k in a)

    W, q, mu = two_contacts
    p = frix.Problem(W, q, mu)
    res = frix.solve(p, tol=1e-10)
    assert same(p.measure(res.r), res.measures)
    assert p.measure(np.zeros(6))["error_scaled"] > 0.1
    with pytest.raises(frix.DimensionError):
        p.measure(np.zeros(5))
    with pytest.raises(frix.InvalidArgumentError):
        p.measure(res.r, v=np.zeros(1))
    M = np.diag([2.0, 3.0, 4.0])
    H = np.eye(3)
    g = frix.Problem.from_global(M, H, np.array([0.0, 0.1, -1.0]), np.zeros(3), np.array([0.5]))
    gres = frix.solve(g, tol=1e-10)
    assert same(g.measure(gres.r, gres.v), gres.measures)
    assert gres.measures["equilibrium"] < 1e-12
    with pytest.raises(frix.InvalidArgumentError):
        g.measure(gres.r)


def test_large_arrays_are_saved_deflated_and_read_back_exactly(tmp_path):
    # Arrays of 1024 entries or more are written in deflated chunks: the file is smaller than
    # its doubles alone, and the problem read back is the same to the bit.
    nc = 2000
    rng = np.random.default_rng(3)
    blocks = [np.diag([2.0, 1.0, 1.0]) for _ in range(nc)]
    W = sp.block_diag(blocks, format="csr")
    q = np.tile([-1.0, 0.0, 0.0], nc) + 1e-3 * np.round(rng.standard_normal(3 * nc), 2)
    mu = np.full(nc, 0.3)
    p = frix.Problem(W, q, mu)
    path = tmp_path / "large.hdf5"
    p.save(path)
    assert path.stat().st_size < 0.5 * 8 * (W.nnz + q.size + mu.size)
    back = frix.load(path)
    assert (back.W != p.W).nnz == 0
    assert np.array_equal(frix.solve(back, tol=1e-10).r, frix.solve(p, tol=1e-10).r)


def test_module_measure_is_the_problems(two_contacts):
    # frix.measure(problem, r, v) gives Problem.measure's dictionary, and refuses alike.
    W, q, mu = two_contacts
    p = frix.Problem(W, q, mu)
    res = frix.solve(p, tol=1e-10)
    assert frix.measure(p, res.r).keys() == p.measure(res.r).keys()
    assert frix.measure(p, res.r)["error_scaled"] == p.measure(res.r)["error_scaled"] < 1e-10
    assert frix.measure(p, np.zeros(6))["error_scaled"] > 0.1
    with pytest.raises(frix.DimensionError):
        frix.measure(p, np.zeros(4))
    g = frix.Problem.from_global(np.diag([2.0, 3.0, 4.0]), np.eye(3), np.array([0.0, 0.1, -1.0]),
                                 np.zeros(3), np.array([0.5]))
    gres = frix.solve(g, tol=1e-10)
    assert frix.measure(g, gres.r, gres.v) == g.measure(gres.r, gres.v)
    assert frix.measure(g, gres.r, gres.v)["equilibrium"] < 1e-12
    assert frix.measure(g, gres.r, np.zeros(3))["equilibrium"] > 0.1  # v = 0 is not in equilibrium
    with pytest.raises(frix.InvalidArgumentError):
        frix.measure(g, gres.r)


def test_info_texts_round_trip(tmp_path, two_contacts):
    # title, description and math_info through save's arguments and the properties, written to
    # FCLIB's info group and read back; line breaks and tabs stay, other control characters
    # come back escaped; a problem saved again keeps what it read.
    p = frix.Problem(*two_contacts)
    assert (p.title, p.description, p.math_info) == ("", "", "")
    path = tmp_path / "texts.hdf5"
    p.save(path, title="two contacts", description="coupled\n\tby W\x1b", math_info="u = W r + q")
    assert (p.title, p.description, p.math_info) == ("two contacts", "coupled\n\tby W\x1b", "u = W r + q")
    back = frix.load(path)
    assert back.title == "two contacts"
    assert back.description == "coupled\n\tby W\\x1b"
    assert back.math_info == "u = W r + q"
    again = tmp_path / "again.hdf5"
    back.save(again)
    assert frix.load(again).description == back.description
    p.description = ""
    p.save(path)
    assert frix.load(path).description.startswith("written by frix ")


def test_info_texts_refused_when_a_file_could_not_carry_them(tmp_path, two_contacts):
    p = frix.Problem(*two_contacts)
    p.description = "d" * 65536
    with pytest.raises(frix.InvalidArgumentError, match="65537 bytes"):
        p.description = "d" * 65537
    assert len(p.description) == 65536  # the text before is kept
    with pytest.raises(frix.InvalidArgumentError, match="NUL"):
        p.math_info = "a\0b"
    with pytest.raises(frix.InvalidArgumentError):
        p.save(tmp_path / "unused.hdf5", title="t" * 70000)
    assert not (tmp_path / "unused.hdf5").exists()


def test_save_compression_is_chosen(tmp_path):
    # compression=True deflates the large arrays (level 4), False stores them plain, an integer
    # is deflate's level; each file reads back the same problem; other values are refused.
    nc = 1000
    W = sp.block_diag([np.diag([2.0, 1.0, 1.0])] * nc, format="csr")
    q = np.tile([-1.0, 0.0, 0.0], nc)
    p = frix.Problem(W, q, np.full(nc, 0.3))
    sizes = []
    for compression in (True, False, 1, 9):
        path = tmp_path / f"c{compression!r}.hdf5"
        p.save(path, compression=compression)
        sizes.append(path.stat().st_size)
        back = frix.load(path)
        assert (back.W != p.W).nnz == 0 and np.array_equal(back.q, q)
    deflated, plain, fastest, smallest = sizes
    assert plain > 8 * (W.count_nonzero() + q.size)  # the doubles, as they are
    assert deflated < plain / 2 and smallest <= fastest < plain / 2
    for bad in (10, -1, 2.5, "yes", None):
        with pytest.raises(frix.InvalidArgumentError, match="compression"):
            p.save(tmp_path / "bad.hdf5", compression=bad)
        assert not (tmp_path / "bad.hdf5").exists()
