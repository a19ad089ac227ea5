"""A real FEM host: the GetFEM example (examples/getfem/block_on_plane.py) against GetFEM's own
frictional contact solver. GetFEM assembles a linear-elastic block pressed onto a tilted rigid
plane and then sheared; frix solves each load step in the global form through one persistent
Solver, GetFEM by Newton on its nodal contact brick (Alart-Curnier). Both must give the same
state (open, stick, slide) at every contact node and the same displacements and forces.
Skipped only where GetFEM is missing (Debian's python3-getfem, which the README installs).
CTest runs this file in a process of its own (test_python_getfem): GetFEM sets OpenBLAS to one
thread when it loads, for the whole process."""
import pathlib
import sys

import numpy as np
import pytest

import frix

pytest.importorskip("getfem", reason="GetFEM is not installed (Debian's python3-getfem)")
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "examples" / "getfem"))
import block_on_plane as host  # noqa: E402  (after the path to the example)


@pytest.fixture(scope="module")
def block():
    return host.Block(10, 10, 4)


def test_frix_and_getfem_agree_at_every_load_step(block):
    solver = frix.Solver(block.problem(host.loads(3)[0]), tol=1e-10)
    seen = set()
    for load in host.loads(3):
        solver.update(f=block.f(load))
        res = solver.solve()
        assert res.converged
        v, r, iterations, _, _ = block.getfem_solve(load)
        # GetFEM's answer solves frix's problem: the two model the same discrete problem.
        assert frix.measure(block.problem(load), r, v)["error_scaled"] < 1e-10
        ours, theirs = block.states(res.r, res.v), block.states(r, v)
        np.testing.assert_array_equal(ours, theirs, err_msg=f"contact states at load {load}")
        seen.update(ours.tolist())
        assert np.abs(res.v - v).max() <= 1e-8 * np.abs(v).max()
        assert np.abs(res.r - r).max() <= 1e-8 * np.abs(r).max()
    # The load path has partial slip: every state occurs.
    assert seen == {host.OPEN, host.STICK, host.SLIDE}
    solver.close()


def test_the_written_problem_is_the_one_solved(tmp_path):
    # The FCLIB file of the last load step carries M, H, f, w, mu, GetFEM's solution and the
    # texts.
    path = tmp_path / "block.hdf5"
    assert host.main(["--mesh", "4", "4", "2", "--steps", "2", "--getfem", "--fclib", str(path)]) == 0
    back = frix.load(path)
    assert back.kind == "global" and back.title.startswith("GetFEM elastic block 4x4x2")
    assert "Coulomb friction 0.3" in back.description
    small = host.Block(4, 4, 2)
    assert (back.M != small.M).nnz == 0 and (back.H != small.H).nnz == 0
    np.testing.assert_array_equal(back.f, small.f(host.loads(2)[-1]))
    r_file, u_file, v_file = frix.load_solution(path, back)
    assert frix.measure(back, r_file, v_file)["error_scaled"] < 1e-10
