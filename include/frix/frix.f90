! frix — the Fortran 2003 binding (ISO_C_BINDING) of the C API in frix.h.
!
!   use frix
!
! Every C function keeps its name and arguments: handles are type(c_ptr), arrays are passed
! as Fortran arrays (contiguous, by reference), scalars by value, int64_t is
! integer(c_int64_t). Indices inside matrices (CSC pointers, row indices, ...) are 0-based,
! as in C. Strings going in must end with c_null_char: use frix_cstr('nsgs'). Strings coming
! out are C pointers: frix_fstr(ptr) copies one into a Fortran string, and
! frix_last_error() is frix_last_error_message() as a Fortran string.
! Fortran names are case-insensitive, so the C constants spelled like a function are
! renamed: FRIX_PROBLEM_LOCAL/GLOBAL are FRIX_PROBLEM_KIND_LOCAL/GLOBAL here, and
! FRIX_INFO_STATUS/ITERATIONS/ERROR are FRIX_INFO_KEY_STATUS/ITERATIONS/ERROR.
! Only the constants that existed when this module was written are here; any other key or
! id of the C headers can be passed as its integer value.
module frix
  use, intrinsic :: iso_c_binding
  implicit none

  ! ---- frix_error
  integer(c_int), parameter :: FRIX_OK = 0, FRIX_ERR_INVALID_ARGUMENT = -1, &
       FRIX_ERR_DIMENSION = -2, FRIX_ERR_NOT_FINITE = -3, FRIX_ERR_OUT_OF_MEMORY = -4, &
       FRIX_ERR_IO = -5, FRIX_ERR_FORMAT = -6, FRIX_ERR_UNKNOWN_SOLVER = -7, &
       FRIX_ERR_UNKNOWN_OPTION = -8, FRIX_ERR_OPTION_RANGE = -9, FRIX_ERR_UNSUPPORTED = -10, &
       FRIX_ERR_NUMERICAL = -11, FRIX_ERR_INTERNAL = -12
  ! ---- frix_status
  integer(c_int), parameter :: FRIX_STATUS_NOT_RUN = 0, FRIX_STATUS_CONVERGED = 1, &
       FRIX_STATUS_MAX_ITER = 2, FRIX_STATUS_TIME_LIMIT = 3, FRIX_STATUS_STAGNATED = 4, &
       FRIX_STATUS_DIVERGED = 5, FRIX_STATUS_NUMERICAL_FAILURE = 6, &
       FRIX_STATUS_STOPPED_BY_CALLBACK = 7
  ! ---- frix_problem_kind
  integer(c_int), parameter :: FRIX_PROBLEM_KIND_LOCAL = 1, FRIX_PROBLEM_KIND_GLOBAL = 2
  ! ---- frix_option_key
  integer(c_int), parameter :: FRIX_OPT_TOLERANCE = 1, FRIX_OPT_MAX_ITER = 2, &
       FRIX_OPT_TIME_LIMIT = 3, FRIX_OPT_VERBOSITY = 4, FRIX_OPT_ERROR_MEASURE = 5, &
       FRIX_OPT_LOCAL_SOLVER = 6, FRIX_OPT_LOCAL_TOLERANCE = 7, FRIX_OPT_LOCAL_MAX_ITER = 8, &
       FRIX_OPT_RELAXATION = 9, FRIX_OPT_SHUFFLE = 10, FRIX_OPT_SEED = 11
  ! ---- solvers
  integer(c_int), parameter :: FRIX_SOLVER_NSGS = 500, FRIX_SOLVER_AUTO = 900
  integer(c_int), parameter :: FRIX_OPT_THREADS = 28, FRIX_OPT_EXISTENCE_CHECK = 29
  ! ---- frix_existence
  integer(c_int), parameter :: FRIX_EXISTENCE_NOT_CHECKED = 0, FRIX_EXISTENCE_GUARANTEED = 1, &
       FRIX_EXISTENCE_DOUBTFUL = 2, FRIX_EXISTENCE_UNDETERMINED = 3
  ! ---- frix_info_key
  integer(c_int), parameter :: FRIX_INFO_KEY_STATUS = 1, FRIX_INFO_KEY_ITERATIONS = 2, &
       FRIX_INFO_SOLVER_ID = 3, FRIX_INFO_CONTACTS = 4, FRIX_INFO_KEY_ERROR = 100, &
       FRIX_INFO_ERROR_RELATIVE = 101, FRIX_INFO_ERROR_Q_RELATIVE = 102, &
       FRIX_INFO_RESIDUAL_ABSOLUTE = 103, FRIX_INFO_CONE_VIOLATION = 104, &
       FRIX_INFO_PENETRATION = 105, FRIX_INFO_COMPLEMENTARITY = 106, &
       FRIX_INFO_EQUILIBRIUM = 107, FRIX_INFO_SOLVE_TIME = 120, FRIX_INFO_TOLERANCE = 121, &
       FRIX_INFO_ISLANDS = 11, FRIX_INFO_SWITCHES = 12, FRIX_INFO_EXISTENCE = 13, &
       FRIX_INFO_EXISTENCE_MARGIN = 124

  interface
    ! ---- version and errors
    function frix_version_string() bind(C, name='frix_version_string')
      import :: c_ptr
      type(c_ptr) :: frix_version_string
    end function
    function frix_version_number() bind(C, name='frix_version_number')
      import :: c_int
      integer(c_int) :: frix_version_number
    end function
    function frix_error_string(code) bind(C, name='frix_error_string')
      import :: c_ptr, c_int
      integer(c_int), value :: code
      type(c_ptr) :: frix_error_string
    end function
    function frix_status_string(status) bind(C, name='frix_status_string')
      import :: c_ptr, c_int
      integer(c_int), value :: status
      type(c_ptr) :: frix_status_string
    end function
    function frix_last_error_message() bind(C, name='frix_last_error_message')
      import :: c_ptr
      type(c_ptr) :: frix_last_error_message
    end function

    ! ---- matrices
    function frix_matrix_from_csc(nrows, ncols, colptr, rowind, values, out) &
         bind(C, name='frix_matrix_from_csc')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nrows, ncols
      integer(c_int64_t), intent(in) :: colptr(*), rowind(*)
      real(c_double), intent(in) :: values(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_matrix_from_csc
    end function
    function frix_matrix_from_csr(nrows, ncols, rowptr, colind, values, out) &
         bind(C, name='frix_matrix_from_csr')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nrows, ncols
      integer(c_int64_t), intent(in) :: rowptr(*), colind(*)
      real(c_double), intent(in) :: values(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_matrix_from_csr
    end function
    function frix_matrix_from_triplets(nrows, ncols, nnz, rows, cols, values, out) &
         bind(C, name='frix_matrix_from_triplets')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nrows, ncols, nnz
      integer(c_int64_t), intent(in) :: rows(*), cols(*)
      real(c_double), intent(in) :: values(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_matrix_from_triplets
    end function
    function frix_matrix_from_dense(nrows, ncols, values, ld, out) &
         bind(C, name='frix_matrix_from_dense')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nrows, ncols
      real(c_double), intent(in) :: values(*)
      integer(c_int64_t), value :: ld
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_matrix_from_dense
    end function
    subroutine frix_matrix_free(m) bind(C, name='frix_matrix_free')
      import :: c_ptr
      type(c_ptr), value :: m
    end subroutine
    function frix_matrix_rows(m) bind(C, name='frix_matrix_rows')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: m
      integer(c_int64_t) :: frix_matrix_rows
    end function
    function frix_matrix_cols(m) bind(C, name='frix_matrix_cols')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: m
      integer(c_int64_t) :: frix_matrix_cols
    end function
    function frix_matrix_nnz(m) bind(C, name='frix_matrix_nnz')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: m
      integer(c_int64_t) :: frix_matrix_nnz
    end function
    function frix_matrix_gemv(m, alpha, x, beta, y) bind(C, name='frix_matrix_gemv')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: m
      real(c_double), value :: alpha, beta
      real(c_double), intent(in) :: x(*)
      real(c_double), intent(inout) :: y(*)
      integer(c_int) :: frix_matrix_gemv
    end function

    ! ---- problems (they borrow the arrays they are built from: keep those alive)
    function frix_problem_local(W, q, mu, nc, out) bind(C, name='frix_problem_local')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: W
      real(c_double), intent(in) :: q(*), mu(*)
      integer(c_int64_t), value :: nc
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_problem_local
    end function
    function frix_problem_global(M, H, f, w, mu, nc, out) bind(C, name='frix_problem_global')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: M, H
      real(c_double), intent(in) :: f(*), w(*), mu(*)
      integer(c_int64_t), value :: nc
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_problem_global
    end function
    subroutine frix_problem_free(p) bind(C, name='frix_problem_free')
      import :: c_ptr
      type(c_ptr), value :: p
    end subroutine
    function frix_problem_get_kind(p) bind(C, name='frix_problem_get_kind')
      import :: c_ptr, c_int
      type(c_ptr), value :: p
      integer(c_int) :: frix_problem_get_kind
    end function
    function frix_problem_contacts(p) bind(C, name='frix_problem_contacts')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: p
      integer(c_int64_t) :: frix_problem_contacts
    end function
    function frix_problem_contact_dofs(p) bind(C, name='frix_problem_contact_dofs')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: p
      integer(c_int64_t) :: frix_problem_contact_dofs
    end function
    function frix_problem_dofs(p) bind(C, name='frix_problem_dofs')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: p
      integer(c_int64_t) :: frix_problem_dofs
    end function
    function frix_problem_set_title(p, title) bind(C, name='frix_problem_set_title')
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: p
      character(kind=c_char), intent(in) :: title(*)
      integer(c_int) :: frix_problem_set_title
    end function

    ! ---- options
    function frix_options_create(solver_id, out) bind(C, name='frix_options_create')
      import :: c_ptr, c_int
      integer(c_int), value :: solver_id
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_options_create
    end function
    subroutine frix_options_free(opts) bind(C, name='frix_options_free')
      import :: c_ptr
      type(c_ptr), value :: opts
    end subroutine
    function frix_options_set_int(opts, key, value) bind(C, name='frix_options_set_int')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: opts
      integer(c_int), value :: key
      integer(c_int64_t), value :: value
      integer(c_int) :: frix_options_set_int
    end function
    function frix_options_set_double(opts, key, value) bind(C, name='frix_options_set_double')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: opts
      integer(c_int), value :: key
      real(c_double), value :: value
      integer(c_int) :: frix_options_set_double
    end function
    function frix_options_get_int(opts, key, value) bind(C, name='frix_options_get_int')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: opts
      integer(c_int), value :: key
      integer(c_int64_t), intent(out) :: value
      integer(c_int) :: frix_options_get_int
    end function
    function frix_options_get_double(opts, key, value) bind(C, name='frix_options_get_double')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: opts
      integer(c_int), value :: key
      real(c_double), intent(out) :: value
      integer(c_int) :: frix_options_get_double
    end function
    function frix_solver_by_name(name, solver_id) bind(C, name='frix_solver_by_name')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*)
      integer(c_int), intent(out) :: solver_id
      integer(c_int) :: frix_solver_by_name
    end function
    function frix_solver_name(solver_id) bind(C, name='frix_solver_name')
      import :: c_ptr, c_int
      integer(c_int), value :: solver_id
      type(c_ptr) :: frix_solver_name
    end function

    ! ---- results and solving
    function frix_info_create(out) bind(C, name='frix_info_create')
      import :: c_ptr, c_int
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_info_create
    end function
    subroutine frix_info_free(info) bind(C, name='frix_info_free')
      import :: c_ptr
      type(c_ptr), value :: info
    end subroutine
    function frix_info_get_int(info, key, value) bind(C, name='frix_info_get_int')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: info
      integer(c_int), value :: key
      integer(c_int64_t), intent(out) :: value
      integer(c_int) :: frix_info_get_int
    end function
    function frix_info_get_double(info, key, value) bind(C, name='frix_info_get_double')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: info
      integer(c_int), value :: key
      real(c_double), intent(out) :: value
      integer(c_int) :: frix_info_get_double
    end function
    function frix_info_status(info) bind(C, name='frix_info_status')
      import :: c_ptr, c_int
      type(c_ptr), value :: info
      integer(c_int) :: frix_info_status
    end function
    function frix_info_iterations(info) bind(C, name='frix_info_iterations')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: info
      integer(c_int64_t) :: frix_info_iterations
    end function
    function frix_info_error(info) bind(C, name='frix_info_error')
      import :: c_ptr, c_double
      type(c_ptr), value :: info
      real(c_double) :: frix_info_error
    end function
    ! r (3nc) is the initial guess and the result; pass c_null_ptr for options or info to use
    ! the defaults or skip the record. v is only read for global problems: for a local one
    ! pass any array (a 1-element dummy is fine).
    function frix_solve(problem, options, r, u, v, info) bind(C, name='frix_solve')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: problem, options, info
      real(c_double), intent(inout) :: r(*)
      real(c_double), intent(out) :: u(*), v(*)
      integer(c_int) :: frix_solve
    end function
    ! What auto did, one line per step (a C string owned by info: frix_fstr copies it).
    function frix_info_trace(info) bind(C, name='frix_info_trace')
      import :: c_ptr
      type(c_ptr), value :: info
      type(c_ptr) :: frix_info_trace
    end function
    function frix_problem_check_existence(problem, time_limit, info) &
         bind(C, name='frix_problem_check_existence')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: problem, info
      real(c_double), value :: time_limit
      integer(c_int) :: frix_problem_check_existence
    end function
    function frix_existence_describe(verdict) bind(C, name='frix_existence_describe')
      import :: c_ptr, c_int
      integer(c_int), value :: verdict
      type(c_ptr) :: frix_existence_describe
    end function
    function frix_problem_error(problem, r, v, error) bind(C, name='frix_problem_error')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: problem
      real(c_double), intent(in) :: r(*), v(*)
      real(c_double), intent(out) :: error
      integer(c_int) :: frix_problem_error
    end function

    ! ---- files (paths end with c_null_char: frix_cstr(path))
    function frix_read_problem(path, out) bind(C, name='frix_read_problem')
      import :: c_ptr, c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_read_problem
    end function
    function frix_fclib_read(path, out) bind(C, name='frix_fclib_read')
      import :: c_ptr, c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_fclib_read
    end function
    function frix_dat_read(path, out) bind(C, name='frix_dat_read')
      import :: c_ptr, c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_dat_read
    end function
    ! The solution and guess arrays are optional in C: pass c_null_ptr or c_loc(array).
    function frix_fclib_write(path, problem, sol_r, sol_u, sol_v, n_guesses, guess_r, &
         guess_u, guess_v) bind(C, name='frix_fclib_write')
      import :: c_ptr, c_int, c_int64_t, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: problem, sol_r, sol_u, sol_v, guess_r, guess_u, guess_v
      integer(c_int64_t), value :: n_guesses
      integer(c_int) :: frix_fclib_write
    end function
    function frix_fclib_read_solution(path, problem, r, u, v) &
         bind(C, name='frix_fclib_read_solution')
      import :: c_ptr, c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: problem, r, u, v
      integer(c_int) :: frix_fclib_read_solution
    end function

    function frix_c_strlen(s) bind(C, name='strlen')
      import :: c_ptr, c_size_t
      type(c_ptr), value :: s
      integer(c_size_t) :: frix_c_strlen
    end function
  end interface

contains

  ! A Fortran string as a C string: trailing blanks removed, c_null_char appended.
  function frix_cstr(s) result(c)
    character(len=*), intent(in) :: s
    character(kind=c_char, len=:), allocatable :: c
    c = trim(s) // c_null_char
  end function

  ! A copy of the C string at p ('' for a null pointer).
  function frix_fstr(p) result(s)
    type(c_ptr), intent(in) :: p
    character(len=:), allocatable :: s
    character(kind=c_char), pointer :: chars(:)
    integer :: i, n
    if (.not. c_associated(p)) then
      s = ''
      return
    end if
    n = int(frix_c_strlen(p))
    call c_f_pointer(p, chars, [n])
    allocate(character(len=n) :: s)
    do i = 1, n
      s(i:i) = chars(i)
    end do
  end function

  ! The message of the last failing frix call in this thread.
  function frix_last_error() result(s)
    character(len=:), allocatable :: s
    s = frix_fstr(frix_last_error_message())
  end function

end module frix
