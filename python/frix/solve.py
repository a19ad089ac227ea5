"""Solving: frix.solve, and frix.Solver, the persistent solver for time stepping."""
import ctypes
import threading
import weakref

import numpy as np

from ._convert import _matrix, _ptr, _vector, _with_values
from ._handle import _Closing
from ._lib import lib
from .errors import DimensionError, InvalidArgumentError, _check, _refusal
from .options import _in_callback, _Options, _settings, _SigintStop
from .problem import _start
from .result import Result, _Info, _Pool


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
    a time limit) for Result.existence: the option existence_check (which wins if also given).
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
        # (frix_solve checked whether a solution exists after a failed run: the option
        # existence_check, which check_existence sets.)
        return Result(info, r, u, v)
    finally:
        problem._release()
        opts.close()


def _entries_a_contact(problem):
    """Entries of r and u a contact: 3, 5 with rolling friction, 6 with spinning friction too."""
    return 6 if problem.spinning else 5 if problem.rolling else 3


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
    Along a line of data (a load path) a solve from the last r starts from the secant of the
    last two answers; secant_start=0 keeps the last r (docs/time-stepping.md).
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
            raise _refusal(InvalidArgumentError, "frix: a Solver cannot be called from its own callback")
        self._lock.acquire()
        if not self._handle:
            self._lock.release()
            raise _refusal(InvalidArgumentError, "frix: the Solver was closed")
        self._busy = True

    def _exit(self):
        self._busy = False
        self._lock.release()

    def solve(self, r0=None):
        """Solves the current problem from r0, or from the last solve's r (0 at first; or the
        secant start's, see Solver)."""
        self._enter()
        try:
            if r0 is not None:
                if not (isinstance(r0, np.ndarray) and r0.shape == self._r.shape):
                    r0 = np.asarray(r0, dtype=np.float64).reshape(-1)
                    if r0.shape != self._r.shape:
                        raise _refusal(DimensionError, f"frix: r0 has {r0.shape[0]} entries, "
                                                       f"expected {self._r.shape[0]}")
                self._r[:] = r0
            info = self._pool.take()
            with _SigintStop(self._opts):
                code = lib.frix_persistent_solve(self._handle, *self._addresses, info.handle)
            self._opts.raise_pending()
            _check(code)
            # (frix_persistent_solve checks existence after a failed run, as frix_solve does.)
            return Result(info, self._r.copy(), self._u.copy(),
                          None if self._v is None else self._v.copy(), self._pool_ref)
        finally:
            self._exit()

    def update(self, q=None, mu=None, W=None, W_values=None, f=None, w=None, M=None, H=None,
               mu_r=None, mu_s=None):
        """The next step's data; what is not given stays. Local problems: q, mu, and W (a new
        matrix, any format) or W_values (new values on the structure of the scipy.sparse W
        the problem was built from, as it was then: in its data's order for csr, csc and coo,
        in W.tocsr()'s for the other formats). Global problems: f, w, mu, M, H. Rolling
        problems (five entries a contact): mu_r too; with spinning friction (six), mu_s too.
        Vectors are borrowed as by Problem (a float64 contiguous array is used in place)."""
        p = self._problem
        nc = self._contacts
        m = _entries_a_contact(p) * nc
        if W_values is not None:
            if W is not None or p._pattern is None or self._contacts != p.contacts:
                raise _refusal(InvalidArgumentError, "frix: W_values needs a problem built from a "
                                                     "scipy.sparse W, and no W, and its contacts")
            W = _with_values(p._pattern, W_values)
        new = {}
        self._enter()
        try:
            if mu_r is not None:
                if not p.rolling:
                    raise _refusal(InvalidArgumentError, "frix: mu_r belongs to rolling-friction problems")
                new["mu_r"] = _vector(mu_r, nc, "mu_r")
                _check(lib.frix_persistent_update_mu_r(self._handle, _ptr(new["mu_r"])))
            if mu_s is not None:
                if not p.spinning:
                    raise _refusal(InvalidArgumentError, "frix: mu_s belongs to problems with spinning friction")
                new["mu_s"] = _vector(mu_s, nc, "mu_s")
                _check(lib.frix_persistent_update_mu_s(self._handle, _ptr(new["mu_s"])))
            if p.kind == "local":
                if any(x is not None for x in (f, w, M, H)):
                    raise _refusal(InvalidArgumentError, "frix: f, w, M, H belong to global problems")
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
                    raise _refusal(InvalidArgumentError, "frix: q and W belong to local problems")
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
            # Coefficients taken before the update was refused: the kept ones again.
            if "mu_r" in new:
                lib.frix_persistent_update_mu_r(self._handle, _ptr(self._current("mu_r")))
            if "mu_s" in new:
                lib.frix_persistent_update_mu_s(self._handle, _ptr(self._current("mu_s")))
            self._discard(new)
            raise
        else:
            self._keep(new)
        finally:
            self._exit()

    def _current(self, name):
        """The coefficients (mu_r, mu_s) the persistent solver borrowed before this call."""
        kept = self._kept.get(name)
        return kept if kept is not None else getattr(self._problem, name)

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

    def set_contacts(self, mu, W=None, q=None, H=None, w=None, mu_r=None, mu_s=None):
        """The next step's contacts, whatever their number nc = len(mu): W (3nc x 3nc) and q
        for a local problem, H (n x 3nc) and w for a global one, with mu, all together
        (frix_persistent_set_contacts_*); a rolling problem takes 5nc for 3nc, and mu_r; one
        with spinning friction 6nc, mu_r and mu_s. M, f and M's factorisation stay. The next
        solve starts from r = 0 unless given r0 (the last r belongs to the old contacts)."""
        p = self._problem
        dim = _entries_a_contact(p)
        mu = np.ascontiguousarray(mu, dtype=np.float64).reshape(-1)
        nc = mu.shape[0]
        new = {}
        self._enter()
        try:
            local = p.kind == "local"
            mat, vec = ("W", "q") if local else ("H", "w")
            given = {"W": W, "q": q, "H": H, "w": w}
            if given[mat] is None or given[vec] is None or any(
                    given[k] is not None for k in given if k not in (mat, vec)) or (
                    (mu_r is not None) != p.rolling) or ((mu_s is not None) != p.spinning):
                extra = ", mu, mu_r and mu_s" if p.spinning else ", mu and mu_r" if p.rolling else " and mu"
                law = " spinning" if p.spinning else " rolling" if p.rolling else ""
                raise _refusal(InvalidArgumentError, f"frix: set_contacts of a {p.kind}{law} problem "
                                                     f"takes {mat}, {vec}{extra}")
            new[mat] = _matrix(given[mat], mat)
            new[vec] = _vector(given[vec], dim * nc, vec)
            new["mu"] = _vector(mu, nc, "mu")
            if p.spinning:
                new["mu_r"], new["mu_s"] = _vector(mu_r, nc, "mu_r"), _vector(mu_s, nc, "mu_s")
                setter = (lib.frix_persistent_set_contacts_spinning_local if local
                          else lib.frix_persistent_set_contacts_spinning_global)
                _check(setter(self._handle, new[mat], _ptr(new[vec]), _ptr(new["mu"]),
                              _ptr(new["mu_r"]), _ptr(new["mu_s"]), nc))
            elif p.rolling:
                new["mu_r"] = _vector(mu_r, nc, "mu_r")
                setter = (lib.frix_persistent_set_contacts_rolling_local if local
                          else lib.frix_persistent_set_contacts_rolling_global)
                _check(setter(self._handle, new[mat], _ptr(new[vec]), _ptr(new["mu"]),
                              _ptr(new["mu_r"]), nc))
            else:
                setter = (lib.frix_persistent_set_contacts_local if local
                          else lib.frix_persistent_set_contacts_global)
                _check(setter(self._handle, new[mat], _ptr(new[vec]), _ptr(new["mu"]), nc))
        except BaseException:
            self._discard(new)
            raise
        else:
            self._keep(new)
            self._contacts = nc
            self._r, self._u = np.zeros(dim * nc), np.zeros(dim * nc)
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
            raise _refusal(InvalidArgumentError, "frix: a Solver cannot be closed from its own callback")
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
