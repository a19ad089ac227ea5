"""Results: frix.Result, its enumerations (Status, Existence) and stage records (Stage), read
from the library's record of the solve (a frix_info) when used."""
import ctypes
import enum
import threading
from collections import namedtuple

import numpy as np

from . import _constants as C
from ._handle import _Handle
from ._lib import lib, text
from .errors import _check


def _enumeration(name, prefix, c_text, doc):
    """The IntEnum of the C enumerators prefix + NAME (_constants.py, in the header's order),
    whose str() and describe() give the library's text for the value (c_text(value))."""
    members = [(k[len(prefix):], v) for k, v in vars(C).items() if k.startswith(prefix)]
    cls = enum.IntEnum(name, members, module=__name__)
    cls.__doc__ = doc

    def describe(self):
        return text(c_text(int(self)))
    cls.describe = cls.__str__ = describe
    return cls


Status = _enumeration("Status", "FRIX_STATUS_", lib.frix_status_string,
                      'How a solve ended (frix_status); str() gives the library\'s text ("converged").')
Existence = _enumeration("Existence", "FRIX_EXISTENCE_", lib.frix_existence_describe,
                         "The existence check's verdict (frix_existence); str() gives the library's text.")

_STATUSES = {s.value: s for s in Status}  # (faster than Status(value) per solve)


def _status(code):
    """A frix.Status, or the plain code of a status newer than this package."""
    return _STATUSES.get(code, code)


# The info keys of Result's dictionaries, by the names they have there.
_COUNTERS = {"newton_iterations": C.FRIX_INFO_NEWTON_ITERATIONS,
             "line_search_steps": C.FRIX_INFO_LINE_SEARCH_STEPS,
             "factorizations": C.FRIX_INFO_FACTORIZATIONS,
             "symbolic_analyses": C.FRIX_INFO_SYMBOLIC_ANALYSES,
             "hybrid_sweeps": C.FRIX_INFO_HYBRID_SWEEPS,
             "inner_iterations": C.FRIX_INFO_INNER_ITERATIONS,
             "islands": C.FRIX_INFO_ISLANDS, "switches": C.FRIX_INFO_SWITCHES}
_MEASURES = {"error_scaled": C.FRIX_INFO_ERROR_SCALED, "error_relative": C.FRIX_INFO_ERROR_RELATIVE,
             "error_q_relative": C.FRIX_INFO_ERROR_Q_RELATIVE,
             "residual_absolute": C.FRIX_INFO_RESIDUAL_ABSOLUTE,
             "cone_violation": C.FRIX_INFO_CONE_VIOLATION, "penetration": C.FRIX_INFO_PENETRATION,
             "complementarity": C.FRIX_INFO_COMPLEMENTARITY, "equilibrium": C.FRIX_INFO_EQUILIBRIUM,
             "error_contact": C.FRIX_INFO_ERROR_CONTACT, "equilibrium_scaled": C.FRIX_INFO_EQUILIBRIUM_SCALED}
_TIMES = {"factorization": C.FRIX_INFO_FACTORIZATION_TIME, "setup": C.FRIX_INFO_SETUP_TIME,
          "reduction": C.FRIX_INFO_REDUCTION_TIME}

# The trace's text and the stages' notes are made in buffers of the frix_info: one reader at
# a time.
_info_text_lock = threading.Lock()


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
        return text(lib.frix_solver_name(_info_int(self._info.handle, C.FRIX_INFO_SOLVER_ID)))

    @property
    def measures(self):
        return {name: _info_double(self._info.handle, key) for name, key in _MEASURES.items()}

    @property
    def counters(self):
        return {name: _info_int(self._info.handle, key) for name, key in _COUNTERS.items()}

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
        return Existence(_info_int(self._info.handle, C.FRIX_INFO_EXISTENCE))

    @property
    def existence_margin(self):
        return _info_double(self._info.handle, C.FRIX_INFO_EXISTENCE_MARGIN)

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
    """The stage records of a frix_info, as Stages."""
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
        sid = geti(C.FRIX_STAGE_SOLVER_ID)
        out.append(Stage(text(lib.frix_solver_name(sid)) if sid else None,
                         _status(geti(C.FRIX_STAGE_STATUS)), geti(C.FRIX_STAGE_ITERATIONS),
                         geti(C.FRIX_STAGE_PART), geti(C.FRIX_STAGE_PART_CONTACTS),
                         geti(C.FRIX_STAGE_RANDOM_STARTS), bool(geti(C.FRIX_STAGE_STOPPED_BY_AUTO)),
                         getd(C.FRIX_STAGE_ERROR), getd(C.FRIX_STAGE_SECONDS),
                         text(lib.frix_info_stage_note(info, k))))
    return out


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

