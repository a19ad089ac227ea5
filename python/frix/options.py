"""Solvers and options: frix.solvers(), the options of a solve (validated by the library), its
progress callback, and Ctrl-C during a solve."""
import ctypes
import signal
import threading
from collections import namedtuple

import numpy as np

from . import _lib
from ._convert import _c_string
from ._handle import _Handle
from ._lib import lib, text
from .errors import OptionRangeError, _check, _refusal


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
                raise _refusal(OptionRangeError,
                               f"frix: option '{name}' takes an integer, not {value!r}")
            v = int(value)
            # Checked here, before the conversion to int64_t wraps it (2**64 + 5 would be 5).
            if not lower.value <= v <= upper.value:
                raise _refusal(OptionRangeError, f"frix: option '{name}' = {v} is outside "
                                                 f"[{int(lower.value)}, {int(upper.value)}]")
            _check(lib.frix_options_set_int(self.handle, key.value, v))
        else:
            try:
                v = float(value)
            except OverflowError:
                raise _refusal(OptionRangeError, f"frix: option '{name}' = {value!r} is outside "
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


def _settings(tol, max_iter, time_limit, solver_options):
    """The options of frix.solve and frix.Solver by name, the common three first."""
    settings = {"tolerance": tol, "max_iter": max_iter, "time_limit": time_limit}
    settings.update(solver_options)
    return settings
