"""Errors: one class per frix_error code, all subclasses of frix.Error, and _check, which
raises the one of a failed call."""
from . import _constants as C
from ._lib import lib, text


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
    C.FRIX_ERR_INVALID_ARGUMENT: InvalidArgumentError, C.FRIX_ERR_DIMENSION: DimensionError,
    C.FRIX_ERR_NOT_FINITE: NotFiniteError, C.FRIX_ERR_OUT_OF_MEMORY: OutOfMemoryError,
    C.FRIX_ERR_IO: FileError, C.FRIX_ERR_FORMAT: FormatError,
    C.FRIX_ERR_UNKNOWN_SOLVER: UnknownSolverError, C.FRIX_ERR_UNKNOWN_OPTION: UnknownOptionError,
    C.FRIX_ERR_OPTION_RANGE: OptionRangeError, C.FRIX_ERR_UNSUPPORTED: UnsupportedError,
    C.FRIX_ERR_NUMERICAL: NumericalError, C.FRIX_ERR_INTERNAL: InternalError,
}
_CODES = {cls: code for code, cls in _ERRORS.items()}


def _check(code):
    """Raises the frix.Error subclass of a failed call, with the library's message."""
    if code != C.FRIX_OK:
        message = text(lib.frix_last_error_message()) or text(lib.frix_error_string(code))
        raise _ERRORS.get(code, Error)(code, message)


def _refusal(cls, message):
    """The error for a call the package refuses itself: cls with its frix_error code, as the
    library would raise it."""
    return cls(_CODES[cls], message)
