"""Shared fixtures: the shared FCLIB data (path given by CTest) and a small problem."""
import os
import pathlib

import numpy as np
import pytest

SHARED = pathlib.Path(os.environ.get("FRIX_SHARED_DIR", pathlib.Path(__file__).parents[3] / "shared"))


@pytest.fixture
def fclib():
    """The shared FCLIB directory; the test is skipped where it is not beside the clone."""
    d = SHARED / "fclib"
    if not d.is_dir():
        pytest.skip(f"{d} not found")
    return d


@pytest.fixture
def two_contacts():
    """(W, q, mu), new arrays for each test: two coupled contacts pressed into the ground, W
    symmetric positive definite."""
    rng = np.random.default_rng(7)
    A = rng.standard_normal((6, 6))
    W = A @ A.T + 6.0 * np.eye(6)
    q = np.array([-1.0, 0.3, -0.2, -0.5, -0.1, 0.4])
    mu = np.array([0.3, 0.5])
    return W, q, mu
