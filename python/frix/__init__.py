"""frix: discrete 3D frictional contact problems with Coulomb friction.

Local form, per contact a 3-vector (normal first): u = W r + q, K* ∋ u + mu |u_T| e_N ⟂ r ∈ K,
K the Coulomb cone |r_T| <= mu r_N. Global form: M v = H r + f, u = H^T v + w.

    import frix
    result = frix.solve(frix.load("problem.hdf5"), tol=1e-6)
    result.status, result.r, result.error

docs/python.md describes the package; every function and class has a docstring.
"""
import ctypes
import enum
import os
import signal
import threading
import warnings
import weakref
from collections import namedtuple

import numpy as np

from . import _lib
from ._lib import lib, text

__all__ = [
    "Problem", "Solver", "Result", "Stage", "Status", "Existence", "SolverInfo",
    "solve", "load", "load_solution", "solvers", "version",
    "Error", "InvalidArgumentError", "DimensionError", "NotFiniteError", "OutOfMemoryError",
    "FileError", "FormatError", "UnknownSolverError", "UnknownOptionError", "OptionRangeError",
    "UnsupportedError", "NumericalError", "InternalError", "ConversionWarning",
]

__version__ = text(lib.frix_version_string()).split()[0]


def version():
    """The library's version string (frix_version_string)."""
    return text(lib.frix_version_string())


# ---- Errors: one class per frix_error code, all subclasses of frix.Error.

class Error(Exception):
    """A call the library refused or could not do; `code` is the frix_error value and the
    message the library's own (frix_last_error_message)."""

    def __init__(self, code, message):
        super().__init__(message)
        self.code = code


class InvalidArgumentError(Error, ValueError):
    """FRIX_ERR_INVALID_ARGUMENT: a missing or bad value."""


class DimensionError(Error, ValueError):
    """FRIX_ERR_DIMENSION: sizes that do not match."""


class NotFiniteError(Error, ValueError):
    """FRIX_ERR_NOT_FINITE: NaN or Inf in the data."""


class OutOfMemoryError(Error, MemoryError):
    """FRIX_ERR_OUT_OF_MEMORY."""


class FileError(Error, OSError):
    """FRIX_ERR_IO: a file cannot be opened, read or written."""


class FormatError(Error, ValueError):
    """FRIX_ERR_FORMAT: a readable file whose content is malformed."""


class UnknownSolverError(Error, ValueError):
    """FRIX_ERR_UNKNOWN_SOLVER."""


class UnknownOptionError(Error, KeyError):
    """FRIX_ERR_UNKNOWN_OPTION: no such option, or the solver does not use it."""

    def __str__(self):  # (KeyError would quote the message)
        return self.args[0] if self.args else ""


class OptionRangeError(Error, ValueError):
    """FRIX_ERR_OPTION_RANGE: an option's value outside its bounds."""


class UnsupportedError(Error):
    """FRIX_ERR_UNSUPPORTED: a valid request this build or solver cannot do."""


class NumericalError(Error, ArithmeticError):
    """FRIX_ERR_NUMERICAL: e.g. a factorisation failed."""


class InternalError(Error):
    """FRIX_ERR_INTERNAL: a bug in frix."""


class ConversionWarning(UserWarning):
    """An input was converted (copied) to float64 or made contiguous."""


_ERRORS = {
    -1: InvalidArgumentError, -2: DimensionError, -3: NotFiniteError, -4: OutOfMemoryError,
    -5: FileError, -6: FormatError, -7: UnknownSolverError, -8: UnknownOptionError,
    -9: OptionRangeError, -10: UnsupportedError, -11: NumericalError, -12: InternalError,
}


def _check(code):
    """Raises the frix.Error subclass of a failed call, with the library's message."""
    if code != 0:
        message = text(lib.frix_last_error_message()) or text(lib.frix_error_string(code))
        raise _ERRORS.get(code, Error)(code, message)


# ---- Enumerations of the C header, by value.

def _library_text(fn):
    """describe() and str() of an enumeration: the library's text for the value."""
    def describe(self):
        return text(fn(int(self)))
    return describe


class Status(enum.IntEnum):
    """How a solve ended (frix_status); str() gives the library's text ("converged")."""
    NOT_RUN = 0
    CONVERGED = 1
    MAX_ITER = 2
    TIME_LIMIT = 3
    STAGNATED = 4
    DIVERGED = 5
    NUMERICAL_FAILURE = 6
    STOPPED_BY_CALLBACK = 7
    MEMORY_LIMIT = 8
    describe = __str__ = _library_text(lib.frix_status_string)


class Existence(enum.IntEnum):
    """The existence check's verdict (frix_existence); str() gives the library's text."""
    NOT_CHECKED = 0
    GUARANTEED = 1
    DOUBTFUL = 2
    UNDETERMINED = 3
    describe = __str__ = _library_text(lib.frix_existence_describe)


_STATUSES = tuple(Status)  # by value (0 .. 8): faster than Status(value) per solve


def _status(code):
    """A frix.Status, or the plain code of a status newer than this package."""
    return _STATUSES[code] if 0 <= code < len(_STATUSES) else code


# The trace's text and the stages' notes are made in buffers of the frix_info: one reader at
# a time.
_info_text_lock = threading.Lock()

_INFO_INT = {"iterations": 2, "newton_iterations": 5, "line_search_steps": 6,
             "factorizations": 7, "symbolic_analyses": 8, "hybrid_sweeps": 9,
             "inner_iterations": 10, "islands": 11, "switches": 12}
_MEASURES = {"error_scaled": 108, "error_relative": 101, "error_q_relative": 102, "residual_absolute": 103,
             "cone_violation": 104, "penetration": 105, "complementarity": 106,
             "equilibrium": 107}
_TIMES = {"factorization": 122, "setup": 123, "reduction": 125}
_INFO_ERROR, _INFO_SOLVE_TIME, _INFO_STATUS, _INFO_SOLVER_ID = 100, 120, 1, 3
_INFO_EXISTENCE, _INFO_EXISTENCE_MARGIN = 13, 124
_FRIX_PROBLEM_LOCAL = 1

# ---- Inputs: vectors borrowed as they are, matrices handed to the library's constructors.


def _vector(x, n, name):
    """x as a float64 C-contiguous 1-D array of n entries: x itself when it is one (the
    library borrows it), else one converted copy, with a ConversionWarning."""
    given = np.asarray(x)
    a = given.reshape(-1) if given.ndim != 1 else given
    # (An empty array shares no memory with anything, not even itself: nothing is copied.)
    copied = a.size > 0 and not np.shares_memory(a, given)
    if a.dtype != np.float64 or not a.flags.c_contiguous or copied:
        warnings.warn(f"frix: {name} converted to a contiguous float64 array (a copy)",
                      ConversionWarning, stacklevel=3)
        a = np.ascontiguousarray(a, dtype=np.float64)
    if a.shape[0] != n:
        raise DimensionError(-2, f"frix: {name} has {a.shape[0]} entries, expected {n}")
    return a


def _c_string(value, what):
    """value (str, bytes or a path) as the NUL-terminated bytes of a C string. An embedded NUL
    is refused: C would read the text only up to it, a different path or name than given."""
    b = os.fsencode(value) if isinstance(value, (bytes, os.PathLike)) else str(value).encode()
    if b"\0" in b:
        raise InvalidArgumentError(-1, f"frix: {what} contains a NUL character: {value!r}")
    return b


def _contacts_of(axis_size, mu):
    """nc from a matrix of 3nc rows or columns (W, H), which the other inputs are checked
    against; from mu where that size is no multiple of 3 (the library then names the matrix)."""
    return axis_size // 3 if axis_size % 3 == 0 else np.asarray(mu).reshape(-1).shape[0]


def _indices(x):
    """Index arrays as int64 (the C API's type): as they are when int64, widened otherwise."""
    return np.ascontiguousarray(x, dtype=np.int64)


def _values(x, name):
    a = np.asarray(x)
    if a.dtype != np.float64 or not a.flags.c_contiguous:
        warnings.warn(f"frix: the values of {name} converted to contiguous float64 (a copy)",
                      ConversionWarning, stacklevel=4)
        a = np.ascontiguousarray(a, dtype=np.float64)
    return a


def _ptr(a, ctype=ctypes.c_double):
    return None if a is None else a.ctypes.data_as(ctypes.POINTER(ctype))


def _is_sparse(A):
    try:
        import scipy.sparse as sp
    except ImportError:  # scipy is optional for dense inputs
        return False
    return sp.issparse(A)


def _matrix(A, name):
    """A frix_matrix handle built from a numpy array or any scipy.sparse matrix or array
    (csr, csc, coo directly; bsr and the other formats through csr). The library copies the
    values into its own storage (its constructors convert as they copy)."""
    out = ctypes.c_void_p()
    if _is_sparse(A):
        fmt = A.format
        if fmt not in ("csr", "csc", "coo"):
            A = A.tocsr()
            fmt = "csr"
        rows, cols = A.shape
        data = _values(A.data, name)
        if fmt == "coo":
            r, c = _indices(A.row), _indices(A.col)
            _check(lib.frix_matrix_from_triplets(rows, cols, data.shape[0], _ptr(r, ctypes.c_int64),
                                                 _ptr(c, ctypes.c_int64), _ptr(data), ctypes.byref(out)))
        else:
            indptr, indices = _indices(A.indptr), _indices(A.indices)
            build = lib.frix_matrix_from_csr if fmt == "csr" else lib.frix_matrix_from_csc
            _check(build(rows, cols, _ptr(indptr, ctypes.c_int64), _ptr(indices, ctypes.c_int64),
                         _ptr(data), ctypes.byref(out)))
    else:
        a = np.asarray(A)
        if a.ndim != 2:
            raise DimensionError(-2, f"frix: {name} must be 2-D, it has {a.ndim} dimensions")
        if a.dtype != np.float64:
            warnings.warn(f"frix: {name} converted to float64 (a copy)", ConversionWarning,
                          stacklevel=3)
        a = np.asfortranarray(a, dtype=np.float64)  # column-major, as frix_matrix_from_dense reads it
        _check(lib.frix_matrix_from_dense(a.shape[0], a.shape[1], _ptr(a), max(1, a.shape[0]),
                                          ctypes.byref(out)))
    return out.value


def _pattern_of(A):
    """The sparsity structure of a scipy.sparse A (copied: later changes to A do not move it),
    for new values on it (Solver.update(W_values=)); None for a dense A."""
    if not _is_sparse(A):
        return None
    if A.format not in ("csr", "csc", "coo"):
        A = A.tocsr()
    if A.format == "coo":
        return ("coo", A.shape, A.row.copy(), A.col.copy(), A.data.shape[0])
    return (A.format, A.shape, A.indptr.copy(), A.indices.copy(), A.data.shape[0])


def _with_values(pattern, values):
    import scipy.sparse as sp
    fmt, shape, a, b, n = pattern
    v = np.asarray(values, dtype=np.float64).reshape(-1)
    if v.shape[0] != n:
        raise DimensionError(-2, f"frix: W_values has {v.shape[0]} entries, expected {n}")
    if fmt == "coo":
        return sp.coo_matrix((v, (a, b)), shape=shape)
    return (sp.csr_matrix if fmt == "csr" else sp.csc_matrix)((v, b, a), shape=shape)


def _vector_property(attr, getter, size, doc):
    """One of a problem's vectors: the array it was given (attr), else a read-only copy of the
    library's (getter) of `size` entries."""
    def get(self):
        given = getattr(self, attr)
        return given if given is not None else self._copy_of(getter, getattr(self, size))
    return property(get, doc=doc)


class _Handle:
    """An object holding a handle of the library: it cannot be copied or pickled (two owners
    would free the handle twice, and a pointer means nothing in another process)."""
    __slots__ = ()

    def __reduce__(self):
        raise TypeError(f"a frix {type(self).__name__} cannot be copied or pickled "
                        "(it holds a handle of the library; copy the arrays you need)")


class _Closing(_Handle):
    """A handle freed by close(), which `with` calls at the block's end."""
    __slots__ = ()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class Problem(_Closing):
    """A local problem, Problem(W, q, mu): u = W r + q with W of 3nc x 3nc (a numpy array or
    any scipy.sparse matrix or array), q of 3nc and mu of nc entries. A global one:
    Problem.from_global(M, H, f, w, mu). Read from a file: frix.load(path).

    q, mu (and f, w) are borrowed, not copied, when they are float64 and contiguous: the
    problem keeps them alive and reads them at every solve, so a time-stepping script may
    change them in place between solves. W, M and H are copied into the library's storage.
    """

    def __init__(self, W, q, mu):
        self._init_state()
        mu_a = np.asarray(mu)
        self._matrices.append(_matrix(W, "W"))
        nc = _contacts_of(lib.frix_matrix_rows(self._matrices[0]), mu_a)
        self._q = _vector(q, 3 * nc, "q")
        self._mu = _vector(mu_a, nc, "mu")
        self._pattern = _pattern_of(W)
        handle = ctypes.c_void_p()
        _check(lib.frix_problem_local(self._matrices[0], _ptr(self._q), _ptr(self._mu), nc,
                                      ctypes.byref(handle)))
        self._handle = handle.value

    @classmethod
    def from_global(cls, M, H, f, w, mu):
        """A global problem: M v = H r + f, u = H^T v + w (M: n x n, H: n x 3nc, f: n, w: 3nc,
        mu: nc)."""
        self = cls.__new__(cls)
        self._init_state()
        mu_a = np.asarray(mu)
        self._matrices.append(_matrix(M, "M"))
        self._matrices.append(_matrix(H, "H"))
        n = lib.frix_matrix_rows(self._matrices[0])
        nc = _contacts_of(lib.frix_matrix_cols(self._matrices[1]), mu_a)
        self._f = _vector(f, n, "f")
        self._w = _vector(w, 3 * nc, "w")
        self._mu = _vector(mu_a, nc, "mu")
        handle = ctypes.c_void_p()
        _check(lib.frix_problem_global(self._matrices[0], self._matrices[1], _ptr(self._f),
                                       _ptr(self._w), _ptr(self._mu), nc, ctypes.byref(handle)))
        self._handle = handle.value
        return self

    @classmethod
    def _owning(cls, handle):
        """A problem that owns its data (read from a file)."""
        self = cls.__new__(cls)
        self._init_state()
        self._handle = handle
        return self

    def _init_state(self):
        self._handle = None
        self._matrices = []
        self._q = self._mu = self._f = self._w = None
        self._pattern = None
        # Solves in progress and open Solvers read the problem: it is freed only without them.
        self._users = 0
        self._users_lock = threading.Lock()
        self._close_pending = False

    def _use(self):
        """The handle, for a solve or a Solver that reads the problem until _release()."""
        with self._users_lock:
            handle = self._live()
            self._users += 1
        return handle

    def _release(self):
        with self._users_lock:
            self._users -= 1
            free = self._close_pending and self._users == 0
        if free:
            self._free()

    def close(self):
        """Frees the library's problem now (also done when the object is collected). Refused
        while a solve of it runs or a frix.Solver made from it is open."""
        with self._users_lock:
            if self._users > 0:
                raise InvalidArgumentError(-1, "frix: the problem is in use (a solve, or an open Solver)")
        self._free()

    def _free(self):
        if self._handle:
            lib.frix_problem_free(self._handle)
            self._handle = None
        for m in self._matrices:
            lib.frix_matrix_free(m)
        self._matrices = []

    def __del__(self):
        if not hasattr(self, "_users_lock"):
            return
        if self._users > 0:
            self._close_pending = True  # (a collected cycle): freed by its last user
        else:
            self._free()

    def _live(self):
        if not self._handle:
            raise InvalidArgumentError(-1, "frix: the problem was closed")
        return self._handle

    @property
    def kind(self):
        """'local' or 'global'."""
        return "local" if lib.frix_problem_get_kind(self._live()) == _FRIX_PROBLEM_LOCAL else "global"

    @property
    def contacts(self):
        """Number of contacts nc."""
        return lib.frix_problem_contacts(self._live())

    @property
    def contact_dofs(self):
        """Size of r and u: 3 nc."""
        return lib.frix_problem_contact_dofs(self._live())

    @property
    def dofs(self):
        """Size of v: n for a global problem, 0 for a local one."""
        return lib.frix_problem_dofs(self._live())

    @property
    def title(self):
        """The problem's free-text title (FCLIB files carry one)."""
        return text(lib.frix_problem_title(self._live()))

    @title.setter
    def title(self, value):
        _check(lib.frix_problem_set_title(self._live(), _c_string(value, "the title")))

    def _copy_of(self, getter, n):
        """A read-only copy of one of the library's vectors (None where the kind has none)."""
        p = getter(self._live())
        if not p:
            return None
        a = np.ctypeslib.as_array(p, shape=(n,)).copy() if n else np.zeros(0)
        a.flags.writeable = False
        return a

    q = _vector_property("_q", lib.frix_problem_q, "contact_dofs",
                         "q (local problems): the array given, or a read-only copy of the library's.")
    mu = _vector_property("_mu", lib.frix_problem_mu, "contacts", "mu, one per contact.")
    f = _vector_property("_f", lib.frix_problem_f, "dofs", "f (global problems).")
    w = _vector_property("_w", lib.frix_problem_w, "contact_dofs", "w (global problems).")

    def _sparse(self, getter):
        import scipy.sparse as sp
        m = getter(self._live())
        if not m:
            return None
        nnz = ctypes.c_int64(0)
        _check(lib.frix_matrix_to_csc(m, ctypes.byref(nnz), None, None, None))
        cols = lib.frix_matrix_cols(m)
        colptr = np.zeros(cols + 1, dtype=np.int64)
        rowind = np.zeros(max(nnz.value, 1), dtype=np.int64)
        values = np.zeros(max(nnz.value, 1))
        _check(lib.frix_matrix_to_csc(m, ctypes.byref(nnz), _ptr(colptr, ctypes.c_int64),
                                      _ptr(rowind, ctypes.c_int64), _ptr(values)))
        return sp.csc_matrix((values[:nnz.value], rowind[:nnz.value], colptr),
                             shape=(lib.frix_matrix_rows(m), cols))

    @property
    def W(self):
        """W as a scipy.sparse CSC matrix (a copy; local problems)."""
        return self._sparse(lib.frix_problem_W)

    @property
    def M(self):
        """M as a scipy.sparse CSC matrix (a copy; global problems)."""
        return self._sparse(lib.frix_problem_M)

    @property
    def H(self):
        """H as a scipy.sparse CSC matrix (a copy; global problems)."""
        return self._sparse(lib.frix_problem_H)

    def save(self, path, solution=None):
        """Writes the problem to a new FCLIB file at path, with a solution when given (a
        Result, or anything with r, u and, for a global problem, v)."""
        r = u = v = None
        if solution is not None:
            m = self.contact_dofs
            r = _vector(solution.r, m, "solution.r")
            u = _vector(solution.u, m, "solution.u")
            if self.kind == "global" and getattr(solution, "v", None) is not None:
                v = _vector(solution.v, self.dofs, "solution.v")
        _check(lib.frix_fclib_write(_c_string(path, "the path"), self._live(), _ptr(r), _ptr(u), _ptr(v),
                                    0, None, None, None))

    def __repr__(self):
        if not self._handle:
            return "<frix.Problem (closed)>"
        extra = f", {self.dofs} dofs" if self.kind == "global" else ""
        return f"<frix.Problem {self.kind}, {self.contacts} contacts{extra}>"


def load(path):
    """Reads a problem from an FCLIB file (.hdf5, local or global) or a Siconos .dat file."""
    handle = ctypes.c_void_p()
    _check(lib.frix_read_problem(_c_string(path, "the path"), ctypes.byref(handle)))
    return Problem._owning(handle.value)


def load_solution(path, problem):
    """The solution stored in an FCLIB file (as `problem.save(path, solution=...)` or `frix solve
    --output` writes it): (r, u, v), v None for a local problem."""
    r, u, v = _start(problem, None)
    _check(lib.frix_fclib_read_solution(_c_string(path, "the path"), problem._live(), _ptr(r), _ptr(u), _ptr(v)))
    return r, u, v


# ---- Solvers and options.

SolverInfo = namedtuple("SolverInfo", "id name description")


def solvers():
    """The registered solvers, as `frix solvers` lists them: (id, name, description)."""
    out = []
    for k in range(lib.frix_solver_count()):
        sid = lib.frix_solver_id_at(k)
        out.append(SolverInfo(sid, text(lib.frix_solver_name(sid)), text(lib.frix_solver_describe(sid))))
    return out


def _solver_id(solver):
    if isinstance(solver, (int, np.integer)):
        return int(solver)
    sid = ctypes.c_int(0)
    _check(lib.frix_solver_by_name(_c_string(solver, "the solver name"), ctypes.byref(sid)))
    return sid.value


# Set while a progress callback runs on this thread: a Solver refuses to be re-entered from
# its own callback (its lock would wait for itself).
_in_callback = threading.local()


def _on_main_thread():
    return threading.current_thread() is threading.main_thread()


class _Options(_Handle):
    """A frix_options handle built from keyword options (validated by the library).

    Its progress callback is installed whenever the solve may need it: for the caller's
    callback, and on the main thread also without one, so that Ctrl-C stops the solve. Python
    runs signal handlers only between bytecodes of the main thread, and while the library
    solves the main thread runs none but the callback's."""

    def __init__(self, solver, settings, callback):
        handle = ctypes.c_void_p()
        _check(lib.frix_options_create(_solver_id(solver), ctypes.byref(handle)))
        self.handle = handle.value
        self.callback = callback
        self.exception = None
        self._fn = None
        try:
            for name, value in settings.items():
                if value is not None:
                    self.set(name, value)
            if callback is not None or _on_main_thread():
                self._fn = _lib.PROGRESS_FN(self._on_progress)
                _check(lib.frix_options_set_callback(self.handle, self._fn, None))
        except BaseException:
            self.close()
            raise

    def set(self, name, value):
        key = ctypes.c_int(0)
        cname = _c_string(name, "the option name")
        _check(lib.frix_option_by_name(cname, ctypes.byref(key)))
        if isinstance(value, (str, bytes)):
            # A choice by name (shuffle="once") or a number as text: the library reads it.
            _check(lib.frix_options_set_by_name(self.handle, cname,
                                                _c_string(value, f"the value of option '{name}'")))
            return
        lower, upper, is_int = ctypes.c_double(), ctypes.c_double(), ctypes.c_int()
        _check(lib.frix_options_bounds(self.handle, key.value, ctypes.byref(lower), ctypes.byref(upper),
                                       ctypes.byref(is_int)))
        if is_int.value:
            try:
                integral = float(value).is_integer()  # (True and False are 1 and 0)
            except OverflowError:  # an int beyond the doubles is integral
                integral = isinstance(value, (int, np.integer))
            if not integral:
                raise OptionRangeError(-9, f"frix: option '{name}' takes an integer, not {value!r}")
            v = int(value)
            # Checked here, before the conversion to int64_t wraps it (2**64 + 5 would be 5).
            if not lower.value <= v <= upper.value:
                raise OptionRangeError(-9, f"frix: option '{name}' = {v} is outside "
                                           f"[{int(lower.value)}, {int(upper.value)}]")
            _check(lib.frix_options_set_int(self.handle, key.value, v))
        else:
            try:
                v = float(value)
            except OverflowError:
                raise OptionRangeError(-9, f"frix: option '{name}' = {value!r} is outside "
                                           f"[{lower.value:g}, {upper.value:g}]") from None
            _check(lib.frix_options_set_double(self.handle, key.value, v))

    def _on_progress(self, _data, iteration, error, elapsed):
        # Called from the solving thread (or auto's workers) with the GIL taken back by ctypes;
        # an exception stops the solve and is raised again once it has returned. Ctrl-C's
        # handler (_SigintStop) runs as this function is entered and only sets its flag.
        if _SigintStop.interrupted:
            return 1
        if self.callback is None:
            return 0
        _in_callback.active = True
        try:
            stop = self.callback(iteration, error, elapsed)
        except BaseException as e:  # noqa: BLE001 (re-raised after the solve)
            self.exception = e
            return 1
        finally:
            _in_callback.active = False
        return 1 if stop or _SigintStop.interrupted else 0

    def raise_pending(self):
        """After a solve: the callback's exception, raised again."""
        if self.exception is not None:
            e, self.exception = self.exception, None
            raise e

    def close(self):
        if getattr(self, "handle", None):
            lib.frix_options_free(self.handle)
            self.handle = None

    def __del__(self):
        self.close()


class _SigintStop:
    """Around one solve on the main thread: Ctrl-C (SIGINT) stops it and raises
    KeyboardInterrupt once the library has returned.

    Python's own handler would raise inside the progress callback, where ctypes can only print
    the exception and go on. So the first solve on the main thread replaces Python's handler
    (signal.default_int_handler) with one that, during a solve, sets a flag the callback
    returns as a stop, and outside solves is Python's handler itself. It stays (setting a
    handler costs more than a small solve); another handler than Python's is left in place."""
    depth = 0            # solves in progress on the main thread (a callback may solve again)
    interrupted = False  # Ctrl-C during one of them

    def __init__(self, opts):
        self.opts = opts
        self.armed = opts._fn is not None and _on_main_thread()

    @staticmethod
    def handler(signum, frame):
        if _SigintStop.depth > 0:
            _SigintStop.interrupted = True
        else:
            signal.default_int_handler(signum, frame)

    def __enter__(self):
        if self.armed:
            current = signal.getsignal(signal.SIGINT)
            if current is signal.default_int_handler:
                signal.signal(signal.SIGINT, _SigintStop.handler)
            elif current is not _SigintStop.handler:
                self.armed = False
        if self.armed:
            _SigintStop.depth += 1
        return self

    def __exit__(self, exc_type, exc, tb):
        if not self.armed:
            return False
        _SigintStop.depth -= 1
        if _SigintStop.interrupted:
            _SigintStop.interrupted = False
            self.opts.exception = None  # (the interrupt wins over the callback's exception)
            raise KeyboardInterrupt
        return False


# ---- Results.

Stage = namedtuple("Stage", "solver status iterations part part_contacts random_starts "
                            "stopped_by_auto error seconds note")
Stage.__doc__ = "One record of a solve's trace: a run of a solver (solver None for another kind of record)."


class Result(_Handle):
    """What a solve returns: r, u (and v for a global problem), status (a frix.Status),
    converged, iterations, error (the measure compared with the tolerance) and time (seconds);
    measures (the other error measures by name), counters (Newton steps, factorisations, ...),
    trace (auto's text) and stages (its records), solver (the name of the solver run), and
    existence / existence_margin (checked when the solve did not converge, if asked). The
    fields but r, u and v are read from the library's record of the solve when used."""

    __slots__ = ("r", "u", "v", "_info", "_pool")

    def __init__(self, info, r, u, v, pool=None):
        self._info = info  # this result's own frix_info
        self._pool = pool  # a weak reference to the Solver's spare infos, where it came from
        self.r, self.u, self.v = r, u, v

    def __del__(self):
        pool = self._pool() if getattr(self, "_pool", None) is not None else None
        if pool is not None and len(pool.items) < _Pool.size:
            pool.items.append(self._info)  # reused by the Solver's next solve

    @property
    def status(self):
        return _status(lib.frix_info_status(self._info.handle))

    @property
    def converged(self):
        return lib.frix_info_status(self._info.handle) == Status.CONVERGED

    @property
    def iterations(self):
        return lib.frix_info_iterations(self._info.handle)

    @property
    def error(self):
        return lib.frix_info_error(self._info.handle)

    @property
    def time(self):
        return lib.frix_info_solve_time(self._info.handle)

    @property
    def times(self):
        return {name: _info_double(self._info.handle, key) for name, key in _TIMES.items()}

    @property
    def solver(self):
        return text(lib.frix_solver_name(_info_int(self._info.handle, _INFO_SOLVER_ID)))

    @property
    def measures(self):
        return {name: _info_double(self._info.handle, key) for name, key in _MEASURES.items()}

    @property
    def counters(self):
        return {name: _info_int(self._info.handle, key) for name, key in _INFO_INT.items()
                if name != "iterations"}

    @property
    def trace(self):
        with _info_text_lock:
            return text(lib.frix_info_trace(self._info.handle))

    @property
    def stages(self):
        with _info_text_lock:
            return _stages(self._info.handle)

    @property
    def existence(self):
        return Existence(_info_int(self._info.handle, _INFO_EXISTENCE))

    @property
    def existence_margin(self):
        return _info_double(self._info.handle, _INFO_EXISTENCE_MARGIN)

    def __repr__(self):
        return (f"<frix.Result {self.status.name}, {self.iterations} iterations, "
                f"error {self.error:.3e}, {self.time:.3g} s>")


def _info_double(info, key):
    x = ctypes.c_double(np.nan)
    lib.frix_info_get_double(info, key, ctypes.byref(x))
    return x.value


def _info_int(info, key):
    x = ctypes.c_int64(0)
    lib.frix_info_get_int(info, key, ctypes.byref(x))
    return x.value


def _stages(info):
    out = []
    for k in range(lib.frix_info_stage_count(info)):
        def geti(key):
            x = ctypes.c_int64(0)
            _check(lib.frix_info_stage_get_int(info, k, key, ctypes.byref(x)))
            return x.value

        def getd(key):
            x = ctypes.c_double(np.nan)
            _check(lib.frix_info_stage_get_double(info, k, key, ctypes.byref(x)))
            return x.value
        sid = geti(1)
        out.append(Stage(text(lib.frix_solver_name(sid)) if sid else None, _status(geti(2)), geti(3),
                         geti(4), geti(5), geti(6), bool(geti(7)), getd(100), getd(101),
                         text(lib.frix_info_stage_note(info, k))))
    return out


# Statuses after which the existence check does not run: a solution, the caller's stop, or
# the caller's time limit (frix_solve checked within it already, with the share it kept).
_NO_EXISTENCE_CHECK = (Status.CONVERGED, Status.STOPPED_BY_CALLBACK, Status.TIME_LIMIT)


def _result(problem, info, r, u, v, check_existence):
    h = info.handle
    if (check_existence and lib.frix_info_status(h) not in _NO_EXISTENCE_CHECK
            and _info_int(h, _INFO_EXISTENCE) == Existence.NOT_CHECKED):
        _check(lib.frix_problem_check_existence(problem, 0.0, h))
    return Result(info, r, u, v)


class _Pool:
    """A Solver's spare frix_info records: a solve takes one, its Result gives it back when it
    is collected (creating one per solve would cost more than a one-contact solve)."""
    size = 4
    __slots__ = ("items", "__weakref__")

    def __init__(self):
        self.items = []

    def take(self):
        return self.items.pop() if self.items else _Info()


class _Info(_Handle):
    """One frix_info record, freed with the object."""

    def __init__(self):
        handle = ctypes.c_void_p()
        _check(lib.frix_info_create(ctypes.byref(handle)))
        self.handle = handle.value

    def __del__(self):
        if getattr(self, "handle", None):
            lib.frix_info_free(self.handle)


def _start(problem, r0):
    m, n = problem.contact_dofs, problem.dofs
    r = np.zeros(m) if r0 is None else np.array(r0, dtype=np.float64, copy=True).reshape(-1)
    if r.shape[0] != m:
        raise DimensionError(-2, f"frix: r0 has {r.shape[0]} entries, expected {m}")
    u = np.zeros(m)
    v = np.zeros(n) if problem.kind == "global" else None
    return r, u, v


def _settings(tol, max_iter, time_limit, solver_options):
    settings = {"tolerance": tol, "max_iter": max_iter, "time_limit": time_limit}
    settings.update(solver_options)
    return settings


def solve(problem, solver="auto", tol=None, max_iter=None, time_limit=None, r0=None,
          callback=None, check_existence=True, **solver_options):
    """Solves `problem` and returns a Result.

    solver: a name or id of frix.solvers() (or Siconos's spelling); tol, max_iter, time_limit
    and any option of that solver by name (see frix.solvers() and `frix solvers NAME`): the
    library validates each one and raises UnknownOptionError or OptionRangeError with its
    message. An option whose values are choices takes their names too: shuffle="once",
    error_measure="siconos", local_solver="newton_ac" (`frix solvers NAME` lists them).
    r0: the warm start (copied; default 0). callback(iteration, error, elapsed): called
    after each iteration; a true return stops the solve (status STOPPED_BY_CALLBACK), an
    exception stops it and is raised again. Ctrl-C stops a solve on the main thread after the
    iteration in progress and raises KeyboardInterrupt, with or without a callback. The GIL is
    released while the library runs.
    check_existence: when the solve ends without a solution (not stopped by the callback),
    whether the library checks whether a solution exists at all (at most about 2 s, or 5 % of
    a time limit) for Result.existence (the option existence_check).
    """
    if not check_existence:
        solver_options.setdefault("existence_check", 0)
    opts = _Options(solver, _settings(tol, max_iter, time_limit, solver_options), callback)
    handle = problem._use()
    try:
        r, u, v = _start(problem, r0)
        info = _Info()
        with _SigintStop(opts):
            code = lib.frix_solve(handle, opts.handle, r.ctypes.data, u.ctypes.data,
                                  None if v is None else v.ctypes.data, info.handle)
        opts.raise_pending()
        _check(code)
        return _result(handle, info, r, u, v, check_existence)
    finally:
        problem._release()
        opts.close()


class Solver(_Closing):
    """A persistent solver for time stepping: created once from a problem and options (those of
    frix.solve), it solves, is updated with the next step's data and solves again, keeping
    between its solves what still holds (factorisations of M, W, analyses; see
    frix_persistent.h). Its calls are serialised (one at a time, from any thread); distinct
    Solvers run at once. Its own progress callback cannot call it.

        s = frix.Solver(problem, tol=1e-6)
        for step in range(steps):
            s.update(q=q_step)
            res = s.solve()          # warm: from the last r
    """

    def __init__(self, problem, solver="auto", tol=None, max_iter=None, time_limit=None,
                 callback=None, **solver_options):
        self._problem = problem
        self._lock = threading.Lock()
        self._busy = False  # a call is in progress (its callback may run)
        self._handle = None
        self._kept = {}  # the arrays and matrices the persistent solver borrows
        self._contacts = problem.contacts  # changed by set_contacts
        self._opts = _Options(solver, _settings(tol, max_iter, time_limit, solver_options), callback)
        handle = ctypes.c_void_p()
        problem_handle = problem._use()
        try:
            _check(lib.frix_persistent_create(problem_handle, self._opts.handle, ctypes.byref(handle)))
        except BaseException:
            problem._release()
            self._opts.close()
            raise
        self._handle = handle.value
        # The solve's buffers, made once: r carries the warm start from one solve to the next.
        self._r, self._u, self._v = _start(problem, None)
        self._addresses = (self._r.ctypes.data, self._u.ctypes.data,
                           None if self._v is None else self._v.ctypes.data)
        self._pool = _Pool()
        self._pool_ref = weakref.ref(self._pool)

    def _enter(self):
        if self._busy and getattr(_in_callback, "active", False):
            raise InvalidArgumentError(-1, "frix: a Solver cannot be called from its own callback")
        self._lock.acquire()
        if not self._handle:
            self._lock.release()
            raise InvalidArgumentError(-1, "frix: the Solver was closed")
        self._busy = True

    def _exit(self):
        self._busy = False
        self._lock.release()

    def solve(self, r0=None):
        """Solves the current problem from r0, or from the last solve's r (0 at first)."""
        self._enter()
        try:
            if r0 is not None:
                if not (isinstance(r0, np.ndarray) and r0.shape == self._r.shape):
                    r0 = np.asarray(r0, dtype=np.float64).reshape(-1)
                    if r0.shape != self._r.shape:
                        raise DimensionError(-2, f"frix: r0 has {r0.shape[0]} entries, "
                                                 f"expected {self._r.shape[0]}")
                self._r[:] = r0
            info = self._pool.take()
            with _SigintStop(self._opts):
                code = lib.frix_persistent_solve(self._handle, *self._addresses, info.handle)
            self._opts.raise_pending()
            _check(code)
            # (No existence check here: after an update the problem handle's data is not the
            # solver's; auto runs its own when it fails.)
            return Result(info, self._r.copy(), self._u.copy(),
                          None if self._v is None else self._v.copy(), self._pool_ref)
        finally:
            self._exit()

    def update(self, q=None, mu=None, W=None, W_values=None, f=None, w=None, M=None, H=None):
        """The next step's data; what is not given stays. Local problems: q, mu, and W (a new
        matrix, any format) or W_values (new values on the structure of the scipy.sparse W
        the problem was built from, as it was then: in its data's order for csr, csc and coo,
        in W.tocsr()'s for the other formats). Global problems: f, w, mu, M, H. Vectors are
        borrowed as by Problem (a float64 contiguous array is used in place)."""
        p = self._problem
        nc = self._contacts
        m = 3 * nc
        if W_values is not None:
            if W is not None or p._pattern is None or self._contacts != p.contacts:
                raise InvalidArgumentError(-1, "frix: W_values needs a problem built from a "
                                           "scipy.sparse W, and no W, and its contacts")
            W = _with_values(p._pattern, W_values)
        new = {}
        self._enter()
        try:
            if p.kind == "local":
                if any(x is not None for x in (f, w, M, H)):
                    raise InvalidArgumentError(-1, "frix: f, w, M, H belong to global problems")
                if W is not None:
                    new["W"] = _matrix(W, "W")
                if q is not None:
                    new["q"] = _vector(q, m, "q")
                if mu is not None:
                    new["mu"] = _vector(mu, nc, "mu")
                _check(lib.frix_persistent_update_local(self._handle, new.get("W"),
                                                        _ptr(new.get("q")), _ptr(new.get("mu"))))
            else:
                if any(x is not None for x in (q, W)):
                    raise InvalidArgumentError(-1, "frix: q and W belong to local problems")
                if M is not None:
                    new["M"] = _matrix(M, "M")
                if H is not None:
                    new["H"] = _matrix(H, "H")
                if f is not None:
                    new["f"] = _vector(f, p.dofs, "f")
                if w is not None:
                    new["w"] = _vector(w, m, "w")
                if mu is not None:
                    new["mu"] = _vector(mu, nc, "mu")
                _check(lib.frix_persistent_update_global(
                    self._handle, new.get("M"), new.get("H"), _ptr(new.get("f")),
                    _ptr(new.get("w")), _ptr(new.get("mu"))))
        except BaseException:
            self._discard(new)
            raise
        else:
            self._keep(new)
        finally:
            self._exit()

    _MATRICES = ("W", "M", "H")

    @staticmethod
    def _discard(new):
        """Frees the matrices made for a call that was refused."""
        for key in Solver._MATRICES:
            if key in new:
                lib.frix_matrix_free(new[key])

    def _keep(self, new):
        """What the persistent solver now borrows, in place of what it borrowed before."""
        for key, value in new.items():
            old = self._kept.get(key)
            if key in Solver._MATRICES and old is not None:
                lib.frix_matrix_free(old)
            self._kept[key] = value

    def set_contacts(self, mu, W=None, q=None, H=None, w=None):
        """The next step's contacts, whatever their number nc = len(mu): W (3nc x 3nc) and q
        for a local problem, H (n x 3nc) and w for a global one, with mu, all together
        (frix_persistent_set_contacts_*). M, f and M's factorisation stay. The next solve
        starts from r = 0 unless given r0 (the last r belongs to the old contacts)."""
        p = self._problem
        mu = np.ascontiguousarray(mu, dtype=np.float64).reshape(-1)
        nc = mu.shape[0]
        new = {}
        self._enter()
        try:
            local = p.kind == "local"
            mat, vec = ("W", "q") if local else ("H", "w")
            given = {"W": W, "q": q, "H": H, "w": w}
            if given[mat] is None or given[vec] is None or any(
                    given[k] is not None for k in given if k not in (mat, vec)):
                raise InvalidArgumentError(-1, f"frix: set_contacts of a {p.kind} problem takes "
                                           f"{mat}, {vec} and mu")
            new[mat] = _matrix(given[mat], mat)
            new[vec] = _vector(given[vec], 3 * nc, vec)
            new["mu"] = _vector(mu, nc, "mu")
            setter = (lib.frix_persistent_set_contacts_local if local
                      else lib.frix_persistent_set_contacts_global)
            _check(setter(self._handle, new[mat], _ptr(new[vec]), _ptr(new["mu"]), nc))
        except BaseException:
            self._discard(new)
            raise
        else:
            self._keep(new)
            self._contacts = nc
            self._r, self._u = np.zeros(3 * nc), np.zeros(3 * nc)
            self._addresses = (self._r.ctypes.data, self._u.ctypes.data,
                               None if self._v is None else self._v.ctypes.data)
        finally:
            self._exit()

    def close(self):
        """Frees the persistent solver now (also done when the object is collected); waits for
        a call in progress on another thread."""
        if not getattr(self, "_handle", None):
            return
        if self._busy and getattr(_in_callback, "active", False):
            raise InvalidArgumentError(-1, "frix: a Solver cannot be closed from its own callback")
        with self._lock:
            if not self._handle:
                return
            lib.frix_persistent_free(self._handle)
            self._handle = None
            for key in ("W", "M", "H"):
                m = self._kept.pop(key, None)
                if m is not None:
                    lib.frix_matrix_free(m)
            self._opts.close()
        self._problem._release()

    def __del__(self):
        if getattr(self, "_handle", None) and hasattr(self, "_lock"):
            self.close()
