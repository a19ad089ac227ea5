"""frix: discrete 3D frictional contact problems with Coulomb friction.

Local form, per contact a 3-vector (normal first): u = W r + q, K* ∋ u + mu |u_T| e_N ⟂ r ∈ K,
K the Coulomb cone |r_T| <= mu r_N. Global form: M v = H r + f, u = H^T v + w.

    import frix
    result = frix.solve(frix.load("problem.hdf5"), tol=1e-6)
    result.status, result.r, result.error

docs/python.md describes the package; every function and class has a docstring.
"""
from ._lib import lib as _library, text as _text
from .errors import (ConversionWarning, DimensionError, Error, FileError, FormatError, InternalError,
                     InvalidArgumentError, NotFiniteError, NumericalError, OptionRangeError,
                     OutOfMemoryError, UnknownOptionError, UnknownSolverError, UnsupportedError)
from .options import SolverInfo, solvers
from .problem import Problem, load, load_solution, measure
from .result import Existence, Result, Stage, Status
from .solve import Solver, solve

__all__ = [
    "Problem", "Solver", "Result", "Stage", "Status", "Existence", "SolverInfo",
    "solve", "measure", "load", "load_solution", "solvers", "version",
    "Error", "InvalidArgumentError", "DimensionError", "NotFiniteError", "OutOfMemoryError",
    "FileError", "FormatError", "UnknownSolverError", "UnknownOptionError", "OptionRangeError",
    "UnsupportedError", "NumericalError", "InternalError", "ConversionWarning",
]

__version__ = _text(_library.frix_version_string()).split()[0]


def version():
    """The library's version string (frix_version_string)."""
    return _text(_library.frix_version_string())


# The public names are frix's wherever they are defined: pickles, reprs and tracebacks say
# frix.Status, frix.DimensionError, as users import them.
for _name in __all__:
    globals()[_name].__module__ = __name__
del _name
