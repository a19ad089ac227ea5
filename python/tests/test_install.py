"""cmake --install puts an importable package that loads the installed library."""
import os
import subprocess
import sys

import pytest


def test_install_puts_an_importable_package(tmp_path):
    """cmake --install into a fresh prefix: the installed package imports from there and loads
    the installed library (relative to itself), not the build tree's."""
    build = os.environ.get("FRIX_INSTALL_TEST_BUILD")
    if not build:
        pytest.skip("FRIX_INSTALL_TEST_BUILD not set (CTest sets it)")
    prefix = tmp_path / "prefix"
    subprocess.run(["cmake", "--install", build, "--prefix", str(prefix)], check=True,
                   capture_output=True)
    found = list(prefix.glob("lib/python3*/dist-packages/frix/__init__.py"))
    assert len(found) == 1
    site = found[0].parent.parent
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "FRIX_LIBRARY")}
    env["PYTHONPATH"] = str(site)
    code = ("import frix, numpy as np; from frix import _lib; "
            "p = frix.Problem(np.eye(3), np.array([-1.0, 0.0, 0.0]), np.array([0.5])); "
            "print(frix.solve(p).status, _lib._path)")
    out = subprocess.run([sys.executable, "-c", code], check=True, capture_output=True, text=True,
                         env=env, cwd=tmp_path).stdout.split()
    assert out[0] == "converged"
    assert os.path.realpath(out[1]).startswith(os.path.realpath(prefix))
