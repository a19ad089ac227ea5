"""Inputs: vectors borrowed as they are, matrices (numpy arrays, any scipy.sparse format)
handed to the library's constructors, and text as C strings."""
import ctypes
import os
import warnings

import numpy as np

from ._lib import lib
from .errors import ConversionWarning, DimensionError, InvalidArgumentError, _check, _refusal


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
        raise _refusal(DimensionError, f"frix: {name} has {a.shape[0]} entries, expected {n}")
    return a


def _c_string(value, what):
    """value (str, bytes or a path) as the NUL-terminated bytes of a C string. An embedded NUL
    is refused: C would read the text only up to it, a different path or name than given."""
    b = os.fsencode(value) if isinstance(value, (bytes, os.PathLike)) else str(value).encode()
    if b"\0" in b:
        raise _refusal(InvalidArgumentError, f"frix: {what} contains a NUL character: {value!r}")
    return b


def _contacts_of(axis_size, mu, dim=3):
    """nc from a matrix of dim nc rows or columns (W, H; dim 5 for rolling friction, 6 with
    spinning friction too), which the other inputs are checked against; from mu where that
    size is no multiple of dim (the library then names the matrix)."""
    return axis_size // dim if axis_size % dim == 0 else np.asarray(mu).reshape(-1).shape[0]


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
            raise _refusal(DimensionError, f"frix: {name} must be 2-D, it has {a.ndim} dimensions")
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
        raise _refusal(DimensionError, f"frix: W_values has {v.shape[0]} entries, expected {n}")
    if fmt == "coo":
        return sp.coo_matrix((v, (a, b)), shape=shape)
    return (sp.csr_matrix if fmt == "csr" else sp.csc_matrix)((v, b, a), shape=shape)
