"""Problems: frix.Problem (local or global, from numpy or scipy, or read from a file), load and
load_solution."""
import ctypes
import threading

import numpy as np

from . import _constants as C
from ._convert import _c_string, _contacts_of, _matrix, _pattern_of, _ptr, _vector
from ._handle import _Closing
from ._lib import lib, text
from .errors import DimensionError, InvalidArgumentError, _check, _refusal
from .result import _MEASURES, _Info, _info_double


def _vector_property(attr, getter, size, doc):
    """One of a problem's vectors: the array it was given (attr), else a read-only copy of the
    library's (getter) of `size` entries."""
    def get(self):
        given = getattr(self, attr)
        return given if given is not None else self._copy_of(getter, getattr(self, size))
    return property(get, doc=doc)


def _text_property(getter, setter, what, doc):
    """One of a problem's texts (at most 65536 bytes; FCLIB's info group carries them)."""
    def get(self):
        return text(getter(self._live()))

    def set_text(self, value):
        _check(setter(self._live(), _c_string(value, what)))
    return property(get, set_text, doc=doc)


class Problem(_Closing):
    """A local problem, Problem(W, q, mu): u = W r + q with W of 3nc x 3nc (a numpy array or
    any scipy.sparse matrix or array), q of 3nc and mu of nc entries. A global one:
    Problem.from_global(M, H, f, w, mu). Read from a file: frix.load(path).

    Rolling friction (rolling resistance): give mu_r (nc entries, each a length >= 0), and
    each contact has five entries, r = (r_N, r_T (2), m_R (2)): W is 5nc x 5nc and q 5nc (H
    has 5nc columns and w 5nc entries). Such a problem's `rolling` is True; the rolling
    solvers (rolling-nsgs, rolling-nsn, and auto, which picks between them) solve it.
    Spinning friction too: give mu_s as well (nc entries >= 0), and each contact has six
    entries, the sixth the moment about the normal (W 6nc x 6nc, q 6nc; H 6nc columns, w
    6nc); `spinning` is then True.

    q, mu (and f, w) are borrowed, not copied, when they are float64 and contiguous: the
    problem keeps them alive and reads them at every solve, so a time-stepping script may
    change them in place between solves. W, M and H are copied into the library's storage.
    """

    def __init__(self, W, q, mu, mu_r=None, mu_s=None):
        self._init_state()
        mu_a = np.asarray(mu)
        dim = _entries_a_contact(mu_r, mu_s)
        self._matrices.append(_matrix(W, "W"))
        nc = _contacts_of(lib.frix_matrix_rows(self._matrices[0]), mu_a, dim)
        self._q = _vector(q, dim * nc, "q")
        self._mu = _vector(mu_a, nc, "mu")
        self._pattern = _pattern_of(W)
        handle = ctypes.c_void_p()
        start = (self._matrices[0], _ptr(self._q), _ptr(self._mu))
        if mu_r is None:
            _check(lib.frix_problem_local(*start, nc, ctypes.byref(handle)))
        elif mu_s is None:
            self._mu_r = _vector(mu_r, nc, "mu_r")
            _check(lib.frix_problem_rolling_local(*start, _ptr(self._mu_r), nc, ctypes.byref(handle)))
        else:
            self._mu_r, self._mu_s = _vector(mu_r, nc, "mu_r"), _vector(mu_s, nc, "mu_s")
            _check(lib.frix_problem_spinning_local(*start, _ptr(self._mu_r), _ptr(self._mu_s), nc,
                                                   ctypes.byref(handle)))
        self._handle = handle.value

    @classmethod
    def from_global(cls, M, H, f, w, mu, mu_r=None, mu_s=None):
        """A global problem: M v = H r + f, u = H^T v + w (M: n x n, H: n x 3nc, f: n, w: 3nc,
        mu: nc); with mu_r (nc), a rolling-friction one (H: n x 5nc, w: 5nc); with mu_r and mu_s
        (nc), rolling and spinning friction (H: n x 6nc, w: 6nc)."""
        self = cls.__new__(cls)
        self._init_state()
        mu_a = np.asarray(mu)
        dim = _entries_a_contact(mu_r, mu_s)
        self._matrices.append(_matrix(M, "M"))
        self._matrices.append(_matrix(H, "H"))
        n = lib.frix_matrix_rows(self._matrices[0])
        nc = _contacts_of(lib.frix_matrix_cols(self._matrices[1]), mu_a, dim)
        self._f = _vector(f, n, "f")
        self._w = _vector(w, dim * nc, "w")
        self._mu = _vector(mu_a, nc, "mu")
        handle = ctypes.c_void_p()
        start = (self._matrices[0], self._matrices[1], _ptr(self._f), _ptr(self._w), _ptr(self._mu))
        if mu_r is None:
            _check(lib.frix_problem_global(*start, nc, ctypes.byref(handle)))
        elif mu_s is None:
            self._mu_r = _vector(mu_r, nc, "mu_r")
            _check(lib.frix_problem_rolling_global(*start, _ptr(self._mu_r), nc, ctypes.byref(handle)))
        else:
            self._mu_r, self._mu_s = _vector(mu_r, nc, "mu_r"), _vector(mu_s, nc, "mu_s")
            _check(lib.frix_problem_spinning_global(*start, _ptr(self._mu_r), _ptr(self._mu_s), nc,
                                                    ctypes.byref(handle)))
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
        self._q = self._mu = self._mu_r = self._mu_s = self._f = self._w = None
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
                raise _refusal(InvalidArgumentError,
                               "frix: the problem is in use (a solve, or an open Solver)")
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
            raise _refusal(InvalidArgumentError, "frix: the problem was closed")
        return self._handle

    @property
    def kind(self):
        """'local' or 'global' (the form; a rolling-friction problem has either, see rolling)."""
        local = (C.FRIX_PROBLEM_LOCAL, C.FRIX_PROBLEM_ROLLING_LOCAL)
        return "local" if lib.frix_problem_get_kind(self._live()) in local else "global"

    @property
    def rolling(self):
        """Whether the problem has rolling friction (five entries a contact, mu_r)."""
        rolling = (C.FRIX_PROBLEM_ROLLING_LOCAL, C.FRIX_PROBLEM_ROLLING_GLOBAL)
        return lib.frix_problem_get_kind(self._live()) in rolling

    @property
    def spinning(self):
        """Whether the problem has spinning friction too (six entries a contact, mu_s)."""
        return bool(lib.frix_problem_mu_s(self._live()))

    @property
    def contacts(self):
        """Number of contacts nc."""
        return lib.frix_problem_contacts(self._live())

    @property
    def contact_dofs(self):
        """Size of r and u: 3 nc (5 nc with rolling friction, 6 nc with spinning friction too)."""
        return lib.frix_problem_contact_dofs(self._live())

    @property
    def dofs(self):
        """Size of v: n for a global problem, 0 for a local one."""
        return lib.frix_problem_dofs(self._live())

    title = _text_property(lib.frix_problem_title, lib.frix_problem_set_title, "the title",
                           "The problem's free-text title (FCLIB's info/title).")
    description = _text_property(lib.frix_problem_description, lib.frix_problem_set_description,
                                 "the description",
                                 "The problem's free-text description (FCLIB's info/description).")
    math_info = _text_property(lib.frix_problem_math_info, lib.frix_problem_set_math_info,
                               "the math info", "The problem's mathematical information, free "
                                                "text (FCLIB's info/math_info).")

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
    mu_r = _vector_property("_mu_r", lib.frix_problem_mu_r, "contacts",
                            "mu_r, one per contact (rolling friction; None otherwise).")
    mu_s = _vector_property("_mu_s", lib.frix_problem_mu_s, "contacts",
                            "mu_s, one per contact (spinning friction; None otherwise).")
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

    def save(self, path, solution=None, title=None, description=None, math_info=None,
             compression=True):
        """Writes the problem to a new FCLIB file at path (an existing file is replaced whole),
        with a solution when given (a Result, or anything with r, u and, for a global problem,
        v). title, description, math_info: set on the problem (as by its properties) before it
        is written; FCLIB's info group carries them. compression: True (deflate's level 4, what
        frix_fclib_write uses), False (none: plain arrays any HDF5 reader takes), or a level
        from 0 to 9; it applies to arrays of 1024 entries or more."""
        if compression is True:
            level = None  # frix_fclib_write's own level
        elif compression is False:
            level = 0
        elif isinstance(compression, (int, np.integer)) and 0 <= compression <= 9:
            level = int(compression)
        else:
            raise _refusal(InvalidArgumentError, f"frix: compression is {compression!r}; expected "
                                                 "True, False or a level from 0 to 9")
        r = u = v = None
        if solution is not None:
            m = self.contact_dofs
            r = _vector(solution.r, m, "solution.r")
            u = _vector(solution.u, m, "solution.u")
            if self.kind == "global" and getattr(solution, "v", None) is not None:
                v = _vector(solution.v, self.dofs, "solution.v")
        for name, value in (("title", title), ("description", description),
                            ("math_info", math_info)):
            if value is not None:
                setattr(self, name, value)
        arguments = (_c_string(path, "the path"), self._live(), _ptr(r), _ptr(u), _ptr(v), 0,
                     None, None, None)
        _check(lib.frix_fclib_write(*arguments) if level is None
               else lib.frix_fclib_write_compressed(*arguments, level))

    def measure(self, r, v=None):
        """The error measures of a given r (and v, required for a global problem) without
        solving, by name as Result.measures gives them: error_scaled (the default measure),
        error_relative (Siconos's), ..., equilibrium (global problems)."""
        r = _vector(r, self.contact_dofs, "r")
        if self.kind == "global":
            v = None if v is None else _vector(v, self.dofs, "v")
        elif v is not None:
            raise _refusal(InvalidArgumentError, "v is given for a local problem (it has no dofs)")
        info = _Info()
        handle = self._use()
        try:
            _check(lib.frix_problem_measure(handle, _ptr(r), _ptr(v), None, info.handle))
        finally:
            self._release()
        return {name: _info_double(info.handle, key) for name, key in _MEASURES.items()}

    def __repr__(self):
        if not self._handle:
            return "<frix.Problem (closed)>"
        extra = f", {self.dofs} dofs" if self.kind == "global" else ""
        rolling = " spinning" if self.spinning else " rolling" if self.rolling else ""
        return f"<frix.Problem {self.kind}{rolling}, {self.contacts} contacts{extra}>"


def _entries_a_contact(mu_r, mu_s):
    """The entries of r and u a contact: 3, 5 with mu_r, 6 with mu_r and mu_s. Spinning friction
    comes with rolling friction (frix_problem.h): mu_s alone is refused."""
    if mu_s is not None and mu_r is None:
        raise _refusal(InvalidArgumentError, "frix: mu_s (spinning friction) needs mu_r (rolling "
                                             "friction; zeros for none)")
    return 3 if mu_r is None else 5 if mu_s is None else 6


def measure(problem, r, v=None):
    """The error measures of a given r (and v, required for a global problem) for `problem`
    without solving: Problem.measure (frix_problem_measure), by the names Result.measures
    gives them. Measures an answer from elsewhere (another solver, a FEM code's own) by frix's
    error measures."""
    return problem.measure(r, v)


def load(path):
    """Reads a problem from an FCLIB file (.hdf5, local or global) or a Siconos .dat file."""
    handle = ctypes.c_void_p()
    _check(lib.frix_read_problem(_c_string(path, "the path"), ctypes.byref(handle)))
    return Problem._owning(handle.value)


def load_solution(path, problem):
    """The solution stored in an FCLIB file (as `problem.save(path, solution=...)` or `frix solve
    --output` writes it): (r, u, v), v None for a local problem."""
    r, u, v = _start(problem, None)
    _check(lib.frix_fclib_read_solution(_c_string(path, "the path"), problem._live(), _ptr(r), _ptr(u),
                                        _ptr(v)))
    return r, u, v


def _start(problem, r0):
    """The arrays of a solve of problem: r from r0 (copied; 0 when None), u, and v for a
    global problem (None for a local one)."""
    m, n = problem.contact_dofs, problem.dofs
    r = np.zeros(m) if r0 is None else np.array(r0, dtype=np.float64, copy=True).reshape(-1)
    if r.shape[0] != m:
        raise _refusal(DimensionError, f"frix: r0 has {r.shape[0]} entries, expected {m}")
    u = np.zeros(m)
    v = np.zeros(n) if problem.kind == "global" else None
    return r, u, v

