"""Shared fixtures: the shared FCLIB data and the frix CLI (paths given by CTest)."""
import os
import pathlib

import pytest

SHARED = pathlib.Path(os.environ.get("FRIX_SHARED_DIR", pathlib.Path(__file__).parents[3] / "shared"))


@pytest.fixture
def fclib():
    """The shared FCLIB directory; the test is skipped where it is not beside the clone."""
    d = SHARED / "fclib"
    if not d.is_dir():
        pytest.skip(f"{d} not found")
    return d
