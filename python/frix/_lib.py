"""The C library through ctypes: loading it and declaring the functions the package calls.

ctypes, not a compiled extension: the package uses libfrix.so.0's stable C ABI exactly as a
plugin host does, needs no compiler or Python headers at install time, and ctypes releases the
GIL for every foreign call (a Python callback takes it back while it runs).
"""
import ctypes
import os
from ctypes import POINTER, c_char_p, c_double, c_int, c_int64, c_void_p

# The library FRIX_LIBRARY names, or the one this package was configured with.
_path = os.environ.get("FRIX_LIBRARY")
if not _path:
    from . import _where
    _path = _where.LIBRARY
lib = ctypes.CDLL(_path)

c_double_p = POINTER(c_double)
c_int64_p = POINTER(c_int64)

# int (*)(void *user_data, int64_t iteration, double error, double elapsed_seconds)
PROGRESS_FN = ctypes.CFUNCTYPE(c_int, c_void_p, c_int64, c_double, c_double)


# The functions declared below, which python/tests/test_headers.py (CTest's
# python_prototypes_match_headers) checks against the headers' prototypes.
DECLARED = []


def _declare(name, restype, *argtypes):
    fn = getattr(lib, name)
    fn.restype = restype
    fn.argtypes = list(argtypes)
    DECLARED.append(name)


_declare("frix_version_string", c_char_p)
_declare("frix_error_string", c_char_p, c_int)
_declare("frix_status_string", c_char_p, c_int)
_declare("frix_last_error_message", c_char_p)
_declare("frix_existence_describe", c_char_p, c_int)

_declare("frix_matrix_from_csr", c_int, c_int64, c_int64, c_int64_p, c_int64_p, c_double_p,
         POINTER(c_void_p))
_declare("frix_matrix_from_csc", c_int, c_int64, c_int64, c_int64_p, c_int64_p, c_double_p,
         POINTER(c_void_p))
_declare("frix_matrix_from_triplets", c_int, c_int64, c_int64, c_int64, c_int64_p, c_int64_p,
         c_double_p, POINTER(c_void_p))
_declare("frix_matrix_from_dense", c_int, c_int64, c_int64, c_double_p, c_int64, POINTER(c_void_p))
_declare("frix_matrix_free", None, c_void_p)
_declare("frix_matrix_rows", c_int64, c_void_p)
_declare("frix_matrix_cols", c_int64, c_void_p)
_declare("frix_matrix_nnz", c_int64, c_void_p)
_declare("frix_matrix_to_csc", c_int, c_void_p, c_int64_p, c_int64_p, c_int64_p, c_double_p)

_declare("frix_problem_local", c_int, c_void_p, c_double_p, c_double_p, c_int64, POINTER(c_void_p))
_declare("frix_problem_global", c_int, c_void_p, c_void_p, c_double_p, c_double_p, c_double_p,
         c_int64, POINTER(c_void_p))
_declare("frix_problem_rolling_local", c_int, c_void_p, c_double_p, c_double_p, c_double_p, c_int64,
         POINTER(c_void_p))
_declare("frix_problem_rolling_global", c_int, c_void_p, c_void_p, c_double_p, c_double_p, c_double_p,
         c_double_p, c_int64, POINTER(c_void_p))
_declare("frix_problem_spinning_local", c_int, c_void_p, c_double_p, c_double_p, c_double_p, c_double_p,
         c_int64, POINTER(c_void_p))
_declare("frix_problem_spinning_global", c_int, c_void_p, c_void_p, c_double_p, c_double_p, c_double_p,
         c_double_p, c_double_p, c_int64, POINTER(c_void_p))
_declare("frix_problem_free", None, c_void_p)
_declare("frix_problem_get_kind", c_int, c_void_p)
_declare("frix_problem_contacts", c_int64, c_void_p)
_declare("frix_problem_contact_dofs", c_int64, c_void_p)
_declare("frix_problem_dofs", c_int64, c_void_p)
_declare("frix_problem_W", c_void_p, c_void_p)
_declare("frix_problem_M", c_void_p, c_void_p)
_declare("frix_problem_H", c_void_p, c_void_p)
_declare("frix_problem_q", c_double_p, c_void_p)
_declare("frix_problem_f", c_double_p, c_void_p)
_declare("frix_problem_w", c_double_p, c_void_p)
_declare("frix_problem_mu", c_double_p, c_void_p)
_declare("frix_problem_mu_r", c_double_p, c_void_p)
_declare("frix_problem_mu_s", c_double_p, c_void_p)
_declare("frix_problem_title", c_char_p, c_void_p)
_declare("frix_problem_set_title", c_int, c_void_p, c_char_p)
_declare("frix_problem_description", c_char_p, c_void_p)
_declare("frix_problem_set_description", c_int, c_void_p, c_char_p)
_declare("frix_problem_math_info", c_char_p, c_void_p)
_declare("frix_problem_set_math_info", c_int, c_void_p, c_char_p)
_declare("frix_read_problem", c_int, c_char_p, POINTER(c_void_p))
_declare("frix_fclib_read_solution", c_int, c_char_p, c_void_p, c_double_p, c_double_p, c_double_p)
_declare("frix_fclib_write", c_int, c_char_p, c_void_p, c_double_p, c_double_p, c_double_p,
         c_int64, c_double_p, c_double_p, c_double_p)
_declare("frix_fclib_write_compressed", c_int, c_char_p, c_void_p, c_double_p, c_double_p,
         c_double_p, c_int64, c_double_p, c_double_p, c_double_p, c_int)

_declare("frix_options_create", c_int, c_int, POINTER(c_void_p))
_declare("frix_options_free", None, c_void_p)
_declare("frix_options_set_int", c_int, c_void_p, c_int, c_int64)
_declare("frix_options_set_double", c_int, c_void_p, c_int, c_double)
_declare("frix_options_get_int", c_int, c_void_p, c_int, c_int64_p)
_declare("frix_options_get_double", c_int, c_void_p, c_int, c_double_p)
_declare("frix_options_bounds", c_int, c_void_p, c_int, c_double_p, c_double_p, POINTER(c_int))
_declare("frix_option_name", c_char_p, c_int)
_declare("frix_option_by_name", c_int, c_char_p, POINTER(c_int))
_declare("frix_options_set_callback", c_int, c_void_p, PROGRESS_FN, c_void_p)
_declare("frix_options_set_by_name", c_int, c_void_p, c_char_p, c_char_p)
_declare("frix_option_choice_name", c_char_p, c_int, c_int64)
_declare("frix_option_choice_by_name", c_int, c_int, c_char_p, c_int64_p)

_declare("frix_info_create", c_int, POINTER(c_void_p))
_declare("frix_info_free", None, c_void_p)
_declare("frix_info_get_int", c_int, c_void_p, c_int, c_int64_p)
_declare("frix_info_get_double", c_int, c_void_p, c_int, c_double_p)
_declare("frix_info_trace", c_char_p, c_void_p)
_declare("frix_info_status", c_int, c_void_p)
_declare("frix_info_iterations", c_int64, c_void_p)
_declare("frix_info_error", c_double, c_void_p)
_declare("frix_info_solve_time", c_double, c_void_p)
_declare("frix_info_stage_count", c_int64, c_void_p)
_declare("frix_info_stage_get_int", c_int, c_void_p, c_int64, c_int, c_int64_p)
_declare("frix_info_stage_get_double", c_int, c_void_p, c_int64, c_int, c_double_p)
_declare("frix_info_stage_note", c_char_p, c_void_p, c_int64)

# The solves take the arrays' addresses as plain pointers: building typed ctypes pointers
# would cost more than a one-contact solve.
_declare("frix_solve", c_int, c_void_p, c_void_p, c_void_p, c_void_p, c_void_p, c_void_p)

_declare("frix_problem_measure", c_int, c_void_p, c_double_p, c_double_p, c_double_p, c_void_p)

_declare("frix_persistent_create", c_int, c_void_p, c_void_p, POINTER(c_void_p))
_declare("frix_persistent_free", None, c_void_p)
_declare("frix_persistent_solve", c_int, c_void_p, c_void_p, c_void_p, c_void_p, c_void_p)
_declare("frix_persistent_update_local", c_int, c_void_p, c_void_p, c_double_p, c_double_p)
_declare("frix_persistent_update_global", c_int, c_void_p, c_void_p, c_void_p, c_double_p,
         c_double_p, c_double_p)
_declare("frix_persistent_set_contacts_local", c_int, c_void_p, c_void_p, c_double_p, c_double_p,
         c_int64)
_declare("frix_persistent_set_contacts_global", c_int, c_void_p, c_void_p, c_double_p, c_double_p,
         c_int64)
_declare("frix_persistent_set_contacts_rolling_local", c_int, c_void_p, c_void_p, c_double_p,
         c_double_p, c_double_p, c_int64)
_declare("frix_persistent_set_contacts_rolling_global", c_int, c_void_p, c_void_p, c_double_p,
         c_double_p, c_double_p, c_int64)
_declare("frix_persistent_update_mu_r", c_int, c_void_p, c_double_p)
_declare("frix_persistent_set_contacts_spinning_local", c_int, c_void_p, c_void_p, c_double_p,
         c_double_p, c_double_p, c_double_p, c_int64)
_declare("frix_persistent_set_contacts_spinning_global", c_int, c_void_p, c_void_p, c_double_p,
         c_double_p, c_double_p, c_double_p, c_int64)
_declare("frix_persistent_update_mu_s", c_int, c_void_p, c_double_p)

_declare("frix_solver_count", c_int64)
_declare("frix_solver_id_at", c_int, c_int64)
_declare("frix_solver_name", c_char_p, c_int)
_declare("frix_solver_describe", c_char_p, c_int)
_declare("frix_solver_by_name", c_int, c_char_p, POINTER(c_int))


def text(b):
    """A C string as str ('' for NULL)."""
    return b.decode("utf-8", "replace") if b else ""
