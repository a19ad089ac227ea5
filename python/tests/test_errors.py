"""Errors: the library's code and message, the argument at fault named, NUL characters refused
in C strings."""
import numpy as np
import pytest

import frix


def test_errors_carry_the_library_code_and_message(tmp_path, two_contacts):
    W, q, mu = two_contacts
    with pytest.raises(frix.DimensionError):
        frix.Problem(W, q[:5], mu)
    with pytest.raises(frix.NotFiniteError) as e:
        frix.Problem(np.where(np.eye(6) > 0, np.nan, W), q, mu)
    assert e.value.code == -3 and isinstance(e.value, ValueError)
    with pytest.raises(frix.FileError):
        frix.load(tmp_path / "missing.hdf5")
    bad = tmp_path / "bad.hdf5"
    bad.write_bytes(b"not an hdf5 file at all")
    with pytest.raises(frix.Error):
        frix.load(bad)
    with pytest.raises(frix.DimensionError):
        frix.solve(frix.Problem(W, q, mu), r0=np.zeros(5))


def test_errors_name_the_argument_at_fault(two_contacts):
    W, q, mu = two_contacts
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


def test_nul_characters_refused(tmp_path, two_contacts):
    p = frix.Problem(*two_contacts)
    for call in (lambda: frix.load(str(tmp_path / "a.hdf5") + "\0.dat"),
                 lambda: p.save(str(tmp_path / "b.hdf5") + "\0x"),
                 lambda: frix.solve(p, solver="nsgs\0ipm"),
                 lambda: frix.solve(p, solver="nsgs", shuffle="once\0"),
                 lambda: setattr(p, "title", "a\0b")):
        with pytest.raises(frix.InvalidArgumentError, match="NUL"):
            call()
    assert not (tmp_path / "b.hdf5").exists()
