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
! Fortran names are case-insensitive, so the C names that differ only in case from another
! are renamed here:
!   FRIX_PROBLEM_LOCAL, FRIX_PROBLEM_GLOBAL     -> FRIX_PROBLEM_KIND_LOCAL, _KIND_GLOBAL
!   FRIX_PROBLEM_ROLLING_LOCAL, _ROLLING_GLOBAL -> FRIX_PROBLEM_KIND_ROLLING_LOCAL,
!                                                  _KIND_ROLLING_GLOBAL
!   FRIX_INFO_STATUS, _ITERATIONS, _ERROR       -> FRIX_INFO_KEY_STATUS, _KEY_ITERATIONS,
!                                                  _KEY_ERROR
!   frix_problem_W (the matrix), frix_problem_w -> frix_problem_W_matrix,
!   (the vector w)                                 frix_problem_w_vector
!   frix_info_solve_time (the function)         -> frix_info_solve_seconds (the key
!                                                  FRIX_INFO_SOLVE_TIME keeps its name)
! Every other constant and function of the C headers is here under its C name (the test
! fortran_binding_complete checks it), except frix_plugin_api, the function table for C
! hosts that dlopen the library.
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
       FRIX_STATUS_STOPPED_BY_CALLBACK = 7, FRIX_STATUS_MEMORY_LIMIT = 8
  ! ---- frix_problem_kind
  integer(c_int), parameter :: FRIX_PROBLEM_KIND_LOCAL = 1, FRIX_PROBLEM_KIND_GLOBAL = 2, &
       FRIX_PROBLEM_KIND_ROLLING_LOCAL = 3, FRIX_PROBLEM_KIND_ROLLING_GLOBAL = 4
  ! ---- frix_option_key
  integer(c_int), parameter :: FRIX_OPT_TOLERANCE = 1, FRIX_OPT_MAX_ITER = 2, &
       FRIX_OPT_TIME_LIMIT = 3, FRIX_OPT_VERBOSITY = 4, FRIX_OPT_ERROR_MEASURE = 5, &
       FRIX_OPT_LOCAL_SOLVER = 6, FRIX_OPT_LOCAL_TOLERANCE = 7, FRIX_OPT_LOCAL_MAX_ITER = 8, &
       FRIX_OPT_RELAXATION = 9, FRIX_OPT_SHUFFLE = 10, FRIX_OPT_SEED = 11, &
       FRIX_OPT_RHO_STRATEGY = 12, FRIX_OPT_RHO = 13, FRIX_OPT_LINE_SEARCH = 14, &
       FRIX_OPT_LINE_SEARCH_MAX_ITER = 15, FRIX_OPT_HYBRID = 16, FRIX_OPT_HYBRID_SWEEPS = 17, &
       FRIX_OPT_PROX_ALPHA = 18, FRIX_OPT_PROX_SIGMA = 19, FRIX_OPT_PROX_NU = 20, &
       FRIX_OPT_INNER_SOLVER = 21, FRIX_OPT_FREEZING = 22, FRIX_OPT_ERROR_FREQUENCY = 23, &
       FRIX_OPT_RHO_ADAPTIVE = 24, FRIX_OPT_INNER_MAX_ITER = 25, &
       FRIX_OPT_INNER_TOLERANCE_RATIO = 26, FRIX_OPT_ACCELERATION = 27, &
       FRIX_OPT_THREADS = 28, FRIX_OPT_EXISTENCE_CHECK = 29, FRIX_OPT_DRIFT_WINDOW = 30, &
       FRIX_OPT_WATCHDOG = 31, FRIX_OPT_MEMORY_LIMIT = 32, &
       FRIX_OPT_ANDERSON = 33, FRIX_OPT_CALLBACK_ESTIMATES = 34, &
       FRIX_OPT_SECANT_START = 35
  ! ---- option values: frix_rho_strategy, frix_line_search, frix_hybrid,
  !      frix_error_measure, frix_shuffle, frix_local_solver
  integer(c_int), parameter :: FRIX_RHO_CONSTANT = 0, FRIX_RHO_SPECTRAL = 1, &
       FRIX_RHO_SPLIT = 2
  integer(c_int), parameter :: FRIX_LINE_SEARCH_NONE = 0, &
       FRIX_LINE_SEARCH_GOLDSTEIN_PRICE = 1, FRIX_LINE_SEARCH_ARMIJO = 2, &
       FRIX_LINE_SEARCH_NONMONOTONE = 3
  integer(c_int), parameter :: FRIX_HYBRID_NONE = 0, FRIX_HYBRID_NSGS = 1
  integer(c_int), parameter :: FRIX_MEASURE_RELATIVE = 0, FRIX_MEASURE_Q_RELATIVE = 1, &
       FRIX_MEASURE_SCALED = 2
  integer(c_int), parameter :: FRIX_SHUFFLE_NONE = 0, FRIX_SHUFFLE_ONCE = 1, &
       FRIX_SHUFFLE_EACH_SWEEP = 2
  integer(c_int), parameter :: FRIX_LOCAL_NEWTON_AC = 550, FRIX_LOCAL_NEWTON_AC_GP = 551, &
       FRIX_LOCAL_PROJECTION = 552, FRIX_LOCAL_PROJECTION_ITERATED = 553, &
       FRIX_LOCAL_NEWTON_FB = 561, FRIX_LOCAL_CLOSED_FORM = 562, FRIX_LOCAL_HYBRID = 565
  ! ---- solvers (the registry's ids)
  integer(c_int), parameter :: FRIX_SOLVER_NSGS = 500, FRIX_SOLVER_NSGS_VELOCITY = 501, &
       FRIX_SOLVER_PROX = 502, FRIX_SOLVER_TFP = 503, FRIX_SOLVER_NSN_AC = 504, &
       FRIX_SOLVER_VI_FPP = 506, FRIX_SOLVER_VI_EG = 507, FRIX_SOLVER_HP = 508, &
       FRIX_SOLVER_NSN_FB = 513, FRIX_SOLVER_ACLM = 516, FRIX_SOLVER_NSN_NM = 520, &
       FRIX_SOLVER_ADMM = 523, FRIX_SOLVER_IPM = 524, FRIX_SOLVER_GLOBAL_NSN_AC = 607, &
       FRIX_SOLVER_GLOBAL_ADMM = 613, FRIX_SOLVER_AUTO = 900, FRIX_SOLVER_GLOBAL_AL_NEWTON = 901, &
       FRIX_SOLVER_GLOBAL_NSGS = 902, FRIX_SOLVER_IPM_ANM = 903, FRIX_SOLVER_ROLLING_NSGS = 3000, &
       FRIX_SOLVER_ROLLING_NSN = 3010
  ! ---- frix_existence
  integer(c_int), parameter :: FRIX_EXISTENCE_NOT_CHECKED = 0, FRIX_EXISTENCE_GUARANTEED = 1, &
       FRIX_EXISTENCE_DOUBTFUL = 2, FRIX_EXISTENCE_UNDETERMINED = 3
  ! ---- frix_info_key
  integer(c_int), parameter :: FRIX_INFO_KEY_STATUS = 1, FRIX_INFO_KEY_ITERATIONS = 2, &
       FRIX_INFO_SOLVER_ID = 3, FRIX_INFO_CONTACTS = 4, FRIX_INFO_NEWTON_ITERATIONS = 5, &
       FRIX_INFO_LINE_SEARCH_STEPS = 6, FRIX_INFO_FACTORIZATIONS = 7, &
       FRIX_INFO_SYMBOLIC_ANALYSES = 8, FRIX_INFO_HYBRID_SWEEPS = 9, &
       FRIX_INFO_INNER_ITERATIONS = 10, FRIX_INFO_KEY_ERROR = 100, &
       FRIX_INFO_ERROR_RELATIVE = 101, FRIX_INFO_ERROR_Q_RELATIVE = 102, &
       FRIX_INFO_RESIDUAL_ABSOLUTE = 103, FRIX_INFO_CONE_VIOLATION = 104, &
       FRIX_INFO_PENETRATION = 105, FRIX_INFO_COMPLEMENTARITY = 106, &
       FRIX_INFO_EQUILIBRIUM = 107, FRIX_INFO_ERROR_SCALED = 108, &
       FRIX_INFO_ERROR_CONTACT = 109, FRIX_INFO_EQUILIBRIUM_SCALED = 110, FRIX_INFO_SOLVE_TIME = 120, FRIX_INFO_TOLERANCE = 121, &
       FRIX_INFO_FACTORIZATION_TIME = 122, FRIX_INFO_SETUP_TIME = 123, &
       FRIX_INFO_ISLANDS = 11, FRIX_INFO_SWITCHES = 12, FRIX_INFO_EXISTENCE = 13, &
       FRIX_INFO_EXISTENCE_MARGIN = 124, FRIX_INFO_REDUCTION_TIME = 125
  ! Keys of the stage records (frix_info_stage_get_int / _double).
  integer(c_int), parameter :: FRIX_STAGE_SOLVER_ID = 1, FRIX_STAGE_STATUS = 2, &
       FRIX_STAGE_ITERATIONS = 3, FRIX_STAGE_PART = 4, FRIX_STAGE_PART_CONTACTS = 5, &
       FRIX_STAGE_RANDOM_STARTS = 6, FRIX_STAGE_STOPPED_BY_AUTO = 7, FRIX_STAGE_ERROR = 100, &
       FRIX_STAGE_SECONDS = 101

  ! The progress callback (frix_options_set_callback): called after each iteration; a
  ! non-zero result stops the solve (FRIX_STATUS_STOPPED_BY_CALLBACK).
  abstract interface
    function frix_progress_fn(user_data, iteration, error, elapsed_seconds) bind(C)
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: user_data
      integer(c_int64_t), value :: iteration
      real(c_double), value :: error, elapsed_seconds
      integer(c_int) :: frix_progress_fn
    end function
    ! The log sink (frix_options_set_log): one progress line, without its newline, as a C
    ! string (frix_fstr copies it).
    subroutine frix_log_fn(user_data, line) bind(C)
      import :: c_ptr
      type(c_ptr), value :: user_data, line
    end subroutine
  end interface

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
    function frix_matrix_from_blocks(nblock_rows, nblock_cols, nblocks, block_rows, &
         block_cols, values, out) bind(C, name='frix_matrix_from_blocks')
      import :: c_int, c_int64_t, c_double, c_ptr
      integer(c_int64_t), value :: nblock_rows, nblock_cols, nblocks
      integer(c_int64_t), intent(in) :: block_rows(*), block_cols(*)
      real(c_double), intent(in) :: values(*)
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_matrix_from_blocks
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
    function frix_matrix_block_count(m) bind(C, name='frix_matrix_block_count')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: m
      integer(c_int64_t) :: frix_matrix_block_count
    end function
    function frix_matrix_is_block(m) bind(C, name='frix_matrix_is_block')
      import :: c_ptr, c_int
      type(c_ptr), value :: m
      integer(c_int) :: frix_matrix_is_block
    end function
    function frix_matrix_gemv(m, alpha, x, beta, y) bind(C, name='frix_matrix_gemv')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: m
      real(c_double), value :: alpha, beta
      real(c_double), intent(in) :: x(*)
      real(c_double), intent(inout) :: y(*)
      integer(c_int) :: frix_matrix_gemv
    end function
    function frix_matrix_gemv_transposed(m, alpha, x, beta, y) &
         bind(C, name='frix_matrix_gemv_transposed')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: m
      real(c_double), value :: alpha, beta
      real(c_double), intent(in) :: x(*)
      real(c_double), intent(inout) :: y(*)
      integer(c_int) :: frix_matrix_gemv_transposed
    end function
    function frix_matrix_diagonal_block(m, k, out) bind(C, name='frix_matrix_diagonal_block')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: m
      integer(c_int64_t), value :: k
      real(c_double), intent(out) :: out(9)
      integer(c_int) :: frix_matrix_diagonal_block
    end function
    ! Call with c_null_ptr arrays to learn nnz, then with c_loc of colptr (cols+1), rowind and
    ! values (nnz each).
    function frix_matrix_to_csc(m, nnz, colptr, rowind, values) &
         bind(C, name='frix_matrix_to_csc')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: m
      integer(c_int64_t), intent(out) :: nnz
      type(c_ptr), value :: colptr, rowind, values
      integer(c_int) :: frix_matrix_to_csc
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
    function frix_problem_rolling_local(W, q, mu, mu_r, nc, out) bind(C, name='frix_problem_rolling_local')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: W
      real(c_double), intent(in) :: q(*), mu(*), mu_r(*)
      integer(c_int64_t), value :: nc
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_problem_rolling_local
    end function
    function frix_problem_rolling_global(M, H, f, w, mu, mu_r, nc, out) &
         bind(C, name='frix_problem_rolling_global')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: M, H
      real(c_double), intent(in) :: f(*), w(*), mu(*), mu_r(*)
      integer(c_int64_t), value :: nc
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_problem_rolling_global
    end function
    function frix_problem_spinning_local(W, q, mu, mu_r, mu_s, nc, out) bind(C, name='frix_problem_spinning_local')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: W
      real(c_double), intent(in) :: q(*), mu(*), mu_r(*), mu_s(*)
      integer(c_int64_t), value :: nc
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_problem_spinning_local
    end function
    function frix_problem_spinning_global(M, H, f, w, mu, mu_r, mu_s, nc, out) &
         bind(C, name='frix_problem_spinning_global')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: M, H
      real(c_double), intent(in) :: f(*), w(*), mu(*), mu_r(*), mu_s(*)
      integer(c_int64_t), value :: nc
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_problem_spinning_global
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
    function frix_problem_title(p) bind(C, name='frix_problem_title')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_title
    end function
    function frix_problem_set_description(p, description) &
         bind(C, name='frix_problem_set_description')
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: p
      character(kind=c_char), intent(in) :: description(*)
      integer(c_int) :: frix_problem_set_description
    end function
    function frix_problem_description(p) bind(C, name='frix_problem_description')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_description
    end function
    function frix_problem_set_math_info(p, math_info) bind(C, name='frix_problem_set_math_info')
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: p
      character(kind=c_char), intent(in) :: math_info(*)
      integer(c_int) :: frix_problem_set_math_info
    end function
    function frix_problem_math_info(p) bind(C, name='frix_problem_math_info')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_math_info
    end function
    ! Views of the problem's data (c_null_ptr where its kind has no such member): matrices
    ! are handles, vectors C pointers to read with c_f_pointer (3nc entries for q, w; nc for
    ! mu; n for f).
    function frix_problem_W_matrix(p) bind(C, name='frix_problem_W')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_W_matrix
    end function
    function frix_problem_M(p) bind(C, name='frix_problem_M')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_M
    end function
    function frix_problem_H(p) bind(C, name='frix_problem_H')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_H
    end function
    function frix_problem_q(p) bind(C, name='frix_problem_q')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_q
    end function
    function frix_problem_f(p) bind(C, name='frix_problem_f')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_f
    end function
    function frix_problem_w_vector(p) bind(C, name='frix_problem_w')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_w_vector
    end function
    function frix_problem_mu(p) bind(C, name='frix_problem_mu')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_mu
    end function
    function frix_problem_mu_r(p) bind(C, name='frix_problem_mu_r')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_mu_r
    end function
    function frix_problem_mu_s(p) bind(C, name='frix_problem_mu_s')
      import :: c_ptr
      type(c_ptr), value :: p
      type(c_ptr) :: frix_problem_mu_s
    end function

    ! ---- options
    function frix_options_create(solver_id, out) bind(C, name='frix_options_create')
      import :: c_ptr, c_int
      integer(c_int), value :: solver_id
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_options_create
    end function
    function frix_options_copy(src, out) bind(C, name='frix_options_copy')
      import :: c_ptr, c_int
      type(c_ptr), value :: src
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_options_copy
    end function
    function frix_options_solver(opts) bind(C, name='frix_options_solver')
      import :: c_ptr, c_int
      type(c_ptr), value :: opts
      integer(c_int) :: frix_options_solver
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
    function frix_options_bounds(opts, key, lower, upper, is_int) &
         bind(C, name='frix_options_bounds')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: opts
      integer(c_int), value :: key
      real(c_double), intent(out) :: lower, upper
      integer(c_int), intent(out) :: is_int
      integer(c_int) :: frix_options_bounds
    end function
    function frix_option_name(key) bind(C, name='frix_option_name')
      import :: c_ptr, c_int
      integer(c_int), value :: key
      type(c_ptr) :: frix_option_name
    end function
    function frix_option_by_name(name, key) bind(C, name='frix_option_by_name')
      import :: c_int, c_char
      character(kind=c_char), intent(in) :: name(*)
      integer(c_int), intent(out) :: key
      integer(c_int) :: frix_option_by_name
    end function
    ! Choice names of options (shuffle, line_search, error_measure, ...): the name of a value
    ! (a C string, c_null_ptr if none), the value of a name, and an option set from text (a
    ! choice name or a number), e.g. frix_options_set_by_name(opts, frix_cstr('shuffle'),
    ! frix_cstr('once')).
    function frix_option_choice_name(key, value) bind(C, name='frix_option_choice_name')
      import :: c_ptr, c_int, c_int64_t
      integer(c_int), value :: key
      integer(c_int64_t), value :: value
      type(c_ptr) :: frix_option_choice_name
    end function
    function frix_option_choice_by_name(key, name, value) bind(C, name='frix_option_choice_by_name')
      import :: c_int, c_char, c_int64_t
      integer(c_int), value :: key
      character(kind=c_char), intent(in) :: name(*)
      integer(c_int64_t), intent(out) :: value
      integer(c_int) :: frix_option_choice_by_name
    end function
    function frix_options_set_by_name(opts, key, value) bind(C, name='frix_options_set_by_name')
      import :: c_ptr, c_int, c_char
      type(c_ptr), value :: opts
      character(kind=c_char), intent(in) :: key(*), value(*)
      integer(c_int) :: frix_options_set_by_name
    end function
    ! fn: c_funloc of a function with the interface frix_progress_fn (c_null_funptr removes
    ! the callback); user_data is handed back to it unchanged.
    function frix_options_set_callback(opts, fn, user_data) &
         bind(C, name='frix_options_set_callback')
      import :: c_ptr, c_funptr, c_int
      type(c_ptr), value :: opts
      type(c_funptr), value :: fn
      type(c_ptr), value :: user_data
      integer(c_int) :: frix_options_set_callback
    end function
    ! fn: c_funloc of a subroutine with the interface frix_log_fn, or c_null_funptr for stderr
    ! (the default); it receives the progress lines of the option verbosity.
    function frix_options_set_log(opts, fn, user_data) bind(C, name='frix_options_set_log')
      import :: c_ptr, c_funptr, c_int
      type(c_ptr), value :: opts
      type(c_funptr), value :: fn
      type(c_ptr), value :: user_data
      integer(c_int) :: frix_options_set_log
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
    function frix_solver_count() bind(C, name='frix_solver_count')
      import :: c_int64_t
      integer(c_int64_t) :: frix_solver_count
    end function
    function frix_solver_id_at(index) bind(C, name='frix_solver_id_at')
      import :: c_int, c_int64_t
      integer(c_int64_t), value :: index
      integer(c_int) :: frix_solver_id_at
    end function
    function frix_solver_describe(solver_id) bind(C, name='frix_solver_describe')
      import :: c_ptr, c_int
      integer(c_int), value :: solver_id
      type(c_ptr) :: frix_solver_describe
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
    function frix_info_solve_seconds(info) bind(C, name='frix_info_solve_time')
      import :: c_ptr, c_double
      type(c_ptr), value :: info
      real(c_double) :: frix_info_solve_seconds
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
    ! The persistent solver (frix_persistent.h): create once, then update and solve every step.
    function frix_persistent_create(problem, options, out) bind(C, name='frix_persistent_create')
      import :: c_ptr, c_int
      type(c_ptr), value :: problem, options
      type(c_ptr), intent(out) :: out
      integer(c_int) :: frix_persistent_create
    end function
    subroutine frix_persistent_free(ps) bind(C, name='frix_persistent_free')
      import :: c_ptr
      type(c_ptr), value :: ps
    end subroutine
    function frix_persistent_solve(ps, r, u, v, info) bind(C, name='frix_persistent_solve')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: ps, info
      real(c_double), intent(inout) :: r(*)
      real(c_double), intent(out) :: u(*), v(*)
      integer(c_int) :: frix_persistent_solve
    end function
    ! Updates: pass c_loc(array) (a target array that stays valid) or c_null_ptr for unchanged.
    function frix_persistent_update_local(ps, W, q, mu) bind(C, name='frix_persistent_update_local')
      import :: c_ptr, c_int
      type(c_ptr), value :: ps, W, q, mu
      integer(c_int) :: frix_persistent_update_local
    end function
    function frix_persistent_update_global(ps, M, H, f, w, mu) bind(C, name='frix_persistent_update_global')
      import :: c_ptr, c_int
      type(c_ptr), value :: ps, M, H, f, w, mu
      integer(c_int) :: frix_persistent_update_global
    end function
    ! The next step's contacts, nc of them (any number): W (or H), q (or w) and mu together.
    function frix_persistent_set_contacts_local(ps, W, q, mu, nc) &
         bind(C, name='frix_persistent_set_contacts_local')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: ps, W, q, mu
      integer(c_int64_t), value :: nc
      integer(c_int) :: frix_persistent_set_contacts_local
    end function
    function frix_persistent_set_contacts_global(ps, H, w, mu, nc) &
         bind(C, name='frix_persistent_set_contacts_global')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: ps, H, w, mu
      integer(c_int64_t), value :: nc
      integer(c_int) :: frix_persistent_set_contacts_global
    end function
    ! Rolling problems: the next step's contacts with their mu_r, and a new mu_r.
    function frix_persistent_set_contacts_rolling_local(ps, W, q, mu, mu_r, nc) &
         bind(C, name='frix_persistent_set_contacts_rolling_local')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: ps, W, q, mu, mu_r
      integer(c_int64_t), value :: nc
      integer(c_int) :: frix_persistent_set_contacts_rolling_local
    end function
    function frix_persistent_set_contacts_rolling_global(ps, H, w, mu, mu_r, nc) &
         bind(C, name='frix_persistent_set_contacts_rolling_global')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: ps, H, w, mu, mu_r
      integer(c_int64_t), value :: nc
      integer(c_int) :: frix_persistent_set_contacts_rolling_global
    end function
    function frix_persistent_update_mu_r(ps, mu_r) bind(C, name='frix_persistent_update_mu_r')
      import :: c_ptr, c_int
      type(c_ptr), value :: ps, mu_r
      integer(c_int) :: frix_persistent_update_mu_r
    end function
    function frix_persistent_set_contacts_spinning_local(ps, W, q, mu, mu_r, mu_s, nc) &
         bind(C, name='frix_persistent_set_contacts_spinning_local')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: ps, W, q, mu, mu_r, mu_s
      integer(c_int64_t), value :: nc
      integer(c_int) :: frix_persistent_set_contacts_spinning_local
    end function
    function frix_persistent_set_contacts_spinning_global(ps, H, w, mu, mu_r, mu_s, nc) &
         bind(C, name='frix_persistent_set_contacts_spinning_global')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: ps, H, w, mu, mu_r, mu_s
      integer(c_int64_t), value :: nc
      integer(c_int) :: frix_persistent_set_contacts_spinning_global
    end function
    function frix_persistent_update_mu_s(ps, mu_s) bind(C, name='frix_persistent_update_mu_s')
      import :: c_ptr, c_int
      type(c_ptr), value :: ps, mu_s
      integer(c_int) :: frix_persistent_update_mu_s
    end function
    ! What auto did, one line per step (a C string owned by info: frix_fstr copies it).
    function frix_info_trace(info) bind(C, name='frix_info_trace')
      import :: c_ptr
      type(c_ptr), value :: info
      type(c_ptr) :: frix_info_trace
    end function
    ! The lines of the trace as data: count, fields by key, and each line (frix_fstr copies it).
    function frix_info_stage_count(info) bind(C, name='frix_info_stage_count')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: info
      integer(c_int64_t) :: frix_info_stage_count
    end function
    function frix_info_stage_get_int(info, index, key, value) &
         bind(C, name='frix_info_stage_get_int')
      import :: c_ptr, c_int, c_int64_t
      type(c_ptr), value :: info
      integer(c_int64_t), value :: index
      integer(c_int), value :: key
      integer(c_int64_t), intent(out) :: value
      integer(c_int) :: frix_info_stage_get_int
    end function
    function frix_info_stage_get_double(info, index, key, value) &
         bind(C, name='frix_info_stage_get_double')
      import :: c_ptr, c_int, c_int64_t, c_double
      type(c_ptr), value :: info
      integer(c_int64_t), value :: index
      integer(c_int), value :: key
      real(c_double), intent(out) :: value
      integer(c_int) :: frix_info_stage_get_double
    end function
    function frix_info_stage_note(info, index) bind(C, name='frix_info_stage_note')
      import :: c_ptr, c_int64_t
      type(c_ptr), value :: info
      integer(c_int64_t), value :: index
      type(c_ptr) :: frix_info_stage_note
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
    ! u (W r + q) is optional: c_null_ptr or c_loc(u); for a local problem v may be any array.
    function frix_problem_measure(problem, r, v, u, info) bind(C, name='frix_problem_measure')
      import :: c_ptr, c_int, c_double
      type(c_ptr), value :: problem, u, info
      real(c_double), intent(in) :: r(*), v(*)
      integer(c_int) :: frix_problem_measure
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
    function frix_fclib_write_compressed(path, problem, sol_r, sol_u, sol_v, n_guesses, &
         guess_r, guess_u, guess_v, level) bind(C, name='frix_fclib_write_compressed')
      import :: c_ptr, c_int, c_int64_t, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: problem, sol_r, sol_u, sol_v, guess_r, guess_u, guess_v
      integer(c_int64_t), value :: n_guesses
      integer(c_int), value :: level
      integer(c_int) :: frix_fclib_write_compressed
    end function
    function frix_fclib_read_solution(path, problem, r, u, v) &
         bind(C, name='frix_fclib_read_solution')
      import :: c_ptr, c_int, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: problem, r, u, v
      integer(c_int) :: frix_fclib_read_solution
    end function
    function frix_fclib_guess_count(path, count) bind(C, name='frix_fclib_guess_count')
      import :: c_int, c_int64_t, c_char
      character(kind=c_char), intent(in) :: path(*)
      integer(c_int64_t), intent(out) :: count
      integer(c_int) :: frix_fclib_guess_count
    end function
    ! index is 0-based; r, u, v as in frix_fclib_read_solution.
    function frix_fclib_read_guess(path, problem, index, r, u, v) &
         bind(C, name='frix_fclib_read_guess')
      import :: c_ptr, c_int, c_int64_t, c_char
      character(kind=c_char), intent(in) :: path(*)
      type(c_ptr), value :: problem, r, u, v
      integer(c_int64_t), value :: index
      integer(c_int) :: frix_fclib_read_guess
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
