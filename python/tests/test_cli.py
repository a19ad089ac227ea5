"""The package and the frix command line give the same answer."""
import os
import subprocess

import numpy as np
import pytest

import frix


def test_same_r_as_the_cli(tmp_path, fclib):
    cli = os.environ.get("FRIX_CLI")
    if not cli:
        pytest.skip("FRIX_CLI not set (CTest sets it)")
    path = fclib / "local" / "LMGC_100_PR_PerioBox-i00361-60-03000.hdf5"
    out = tmp_path / "cli.hdf5"
    subprocess.run([cli, "solve", str(path), "--tol", "1e-10", "--output", str(out), "-q"],
                   check=True, capture_output=True)
    p = frix.load(path)
    r_cli, u_cli, _ = frix.load_solution(out, p)
    res = frix.solve(p, tol=1e-10)
    np.testing.assert_array_equal(res.r, r_cli)
    np.testing.assert_array_equal(res.u, u_cli)
