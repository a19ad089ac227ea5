! A progress callback written in Fortran: counts its calls in the integer user_data points
! to and asks to stop at the second iteration.
module test_fortran_callback
  use, intrinsic :: iso_c_binding
  implicit none
contains
  function stop_at_two(user_data, iteration, error, elapsed_seconds) result(stop) bind(C)
    type(c_ptr), value :: user_data
    integer(c_int64_t), value :: iteration
    real(c_double), value :: error, elapsed_seconds
    integer(c_int) :: stop
    integer(c_int), pointer :: calls
    call c_f_pointer(user_data, calls)
    calls = calls + 1
    stop = 0
    if (iteration >= 2 .and. error >= 0d0 .and. elapsed_seconds >= 0d0) stop = 1
  end function

  ! A log sink written in Fortran: counts the lines in the integer user_data points to.
  subroutine count_lines(user_data, line) bind(C)
    type(c_ptr), value :: user_data, line
    integer(c_int), pointer :: lines
    call c_f_pointer(user_data, lines)
    if (c_associated(line)) lines = lines + 1
  end subroutine
end module test_fortran_callback

! The Fortran binding (include/frix/frix.f90) end to end: constants, strings both ways,
! errors with messages, matrices, a solve checked by an independent error, options by key
! and by name, the registry, a Fortran progress callback, views of the problem's data, and
! an FCLIB round trip through c_loc. Prints one line per check; exits non-zero on a failure.
program test_fortran
  use, intrinsic :: iso_c_binding
  use frix
  use test_fortran_callback
  implicit none
  integer :: failures = 0, passed = 0
  real(c_double), target :: Wd(9) = [4d0, 1d0, 0d0, 1d0, 3d0, 0d0, 0d0, 0d0, 3d0]
  real(c_double), target :: Bd(9) = [1d0, 2d0, 3d0, 4d0, 5d0, 6d0, 7d0, 8d0, 9d0]
  real(c_double), target :: q(3) = [-2d0, 0.5d0, 0.1d0], mu(1) = [0.4d0]
  real(c_double), target :: r(3), u(3), r2(3), dummy(1)
  ! Data the shapes' problems borrow: named, so that it outlives them.
  real(c_double), target :: f_two(2) = [1d0, -2d0], q_separating(3) = [1d0, 0.5d0, 0d0]
  real(c_double), target :: q_touching(3) = [0d0, 1d0, 0d0], mu_zero(1) = [0d0]
  real(c_double), target :: q_next(3) = [-1d0, 0.2d0, 0d0]
  real(c_double) :: err_value, tol
  real(c_double) :: lower, upper, block(9), y(3)
  real(c_double), pointer :: view(:)
  real(c_double), allocatable, target :: csc_values(:)
  integer(c_int64_t), allocatable, target :: csc_colptr(:), csc_rowind(:)
  integer(c_int64_t) :: n64, k
  integer(c_int), target :: calls, lines
  integer(c_int) :: err, id, key, is_int
  logical :: found
  type(c_ptr) :: W, Wb, p, back, opts, opts2, info, shape, Ms, Hs, ps
  character(len=:), allocatable :: path

  call check('version string', len(frix_fstr(frix_version_string())) > 0)
  call check('version number', frix_version_number() >= 100)
  call check('error string', frix_fstr(frix_error_string(FRIX_ERR_IO)) == 'input/output error')
  err = frix_solver_by_name(frix_cstr('FRICTION_3D_NSGS'), id)
  call check('Siconos solver name', err == FRIX_OK .and. id == FRIX_SOLVER_NSGS)
  call check('solver name', frix_fstr(frix_solver_name(FRIX_SOLVER_NSGS)) == 'nsgs')

  ! A refused call returns its code and leaves a message naming the cause.
  err = frix_matrix_from_dense(3_c_int64_t, 3_c_int64_t, Wd, 2_c_int64_t, W)
  call check('bad leading dimension refused', err == FRIX_ERR_DIMENSION)
  call check('message', index(frix_last_error(), 'leading dimension') > 0)
  err = frix_solver_by_name(frix_cstr('no-such-solver'), id)
  call check('unknown solver', err == FRIX_ERR_UNKNOWN_SOLVER)

  err = frix_matrix_from_dense(3_c_int64_t, 3_c_int64_t, Wd, 3_c_int64_t, W)
  call check('dense matrix', err == FRIX_OK .and. frix_matrix_nnz(W) == 9)
  err = frix_problem_local(W, q, mu, 1_c_int64_t, p)
  call check('local problem', err == FRIX_OK .and. frix_problem_contacts(p) == 1 .and. &
       frix_problem_get_kind(p) == FRIX_PROBLEM_KIND_LOCAL)

  err = frix_options_create(FRIX_SOLVER_NSGS, opts)
  call check('options', err == FRIX_OK)
  err = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, -1d0)
  call check('out-of-range tolerance refused', err == FRIX_ERR_OPTION_RANGE)
  err = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, 1d-12)
  err = frix_options_get_double(opts, FRIX_OPT_TOLERANCE, tol)
  call check('tolerance set', err == FRIX_OK .and. tol == 1d-12)
  err = frix_options_set_int(opts, FRIX_OPT_MAX_ITER, 500_c_int64_t)
  err = frix_options_get_int(opts, FRIX_OPT_MAX_ITER, n64)
  call check('max_iter set', err == FRIX_OK .and. n64 == 500)

  r = 0
  err = frix_info_create(info)
  err = frix_solve(p, opts, r, u, dummy, info)
  call check('solve', err == FRIX_OK .and. frix_info_status(info) == FRIX_STATUS_CONVERGED)
  err = frix_problem_error(p, r, dummy, err_value)
  call check('independent error', err == FRIX_OK .and. err_value <= 1d-12)
  err = frix_info_get_int(info, FRIX_INFO_KEY_ITERATIONS, n64)
  call check('info by key', err == FRIX_OK .and. n64 == frix_info_iterations(info))
  call check('u = W r + q', abs(u(1) - (4d0 * r(1) + r(2) - 2d0)) < 1d-12)

  ! The persistent solver: the same answer as frix_solve, then the next q.
  err = frix_persistent_create(p, opts, ps)
  call check('persistent create', err == FRIX_OK .and. c_associated(ps))
  r2 = 0
  err = frix_persistent_solve(ps, r2, u, dummy, info)
  call check('persistent solve', err == FRIX_OK .and. frix_info_status(info) == FRIX_STATUS_CONVERGED &
             .and. maxval(abs(r2 - r)) <= 1d-10 * maxval(abs(r)))
  err = frix_persistent_update_local(ps, c_null_ptr, c_loc(q_next), c_null_ptr)
  call check('persistent update', err == FRIX_OK)
  err = frix_persistent_solve(ps, r2, u, dummy, info)
  call check('persistent next step', err == FRIX_OK .and. frix_info_status(info) == FRIX_STATUS_CONVERGED &
             .and. abs(u(1) - (4d0 * r2(1) + r2(2) - 1d0)) < 1d-12)
  err = frix_persistent_update_global(ps, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr, c_null_ptr)
  call check('persistent: a local problem takes no global update', err == FRIX_ERR_INVALID_ARGUMENT)
  call frix_persistent_free(ps)

  ! The default solver (auto): its trace, and the existence check.
  r = 0
  err = frix_solve(p, c_null_ptr, r, u, dummy, info)
  err = frix_info_get_int(info, FRIX_INFO_SOLVER_ID, n64)
  call check('default solver is auto', err == FRIX_OK .and. n64 == FRIX_SOLVER_AUTO)
  call check('auto trace', index(frix_fstr(frix_info_trace(info)), 'analysis:') == 1)
  n64 = -1
  err = frix_info_get_int(info, FRIX_INFO_SOLVER_ID, n64)
  k = frix_info_stage_count(info)
  err = frix_info_stage_get_int(info, k - 1_c_int64_t, FRIX_STAGE_SOLVER_ID, n64)
  call check('stage records', k >= 2 .and. err == FRIX_OK .and. n64 > 0 .and. &
       len(frix_fstr(frix_info_stage_note(info, 0_c_int64_t))) > 0)
  err = frix_info_stage_get_double(info, k - 1_c_int64_t, FRIX_STAGE_ERROR, err_value)
  call check('stage error', err == FRIX_OK .and. err_value <= 1d-8)
  err = frix_info_stage_get_int(info, k, FRIX_STAGE_STATUS, n64)
  call check('stage out of range', err == FRIX_ERR_DIMENSION)
  err = frix_problem_check_existence(p, 0d0, info)
  err = frix_info_get_int(info, FRIX_INFO_EXISTENCE, n64)
  call check('existence', err == FRIX_OK .and. n64 == FRIX_EXISTENCE_GUARANTEED .and. &
       frix_fstr(frix_existence_describe(int(n64, c_int))) == 'a solution exists')

  call check('solve time', frix_info_solve_seconds(info) >= 0d0)

  ! The registry and option names.
  found = .false.
  do k = 0, frix_solver_count() - 1
    found = found .or. frix_solver_id_at(k) == FRIX_SOLVER_IPM
  end do
  call check('registry lists ipm', found .and. frix_solver_id_at(frix_solver_count()) == -1)
  call check('solver description', &
       index(frix_fstr(frix_solver_describe(FRIX_SOLVER_NSGS_VELOCITY)), 'Gauss-Seidel') > 0)
  err = frix_option_by_name(frix_cstr('drift_window'), key)
  call check('option by name', err == FRIX_OK .and. key == FRIX_OPT_DRIFT_WINDOW)
  call check('option name', frix_fstr(frix_option_name(FRIX_OPT_LOCAL_SOLVER)) == 'local_solver')

  ! Options of nsgs-v, their bounds, a copy, and values named by the module's constants.
  err = frix_options_create(FRIX_SOLVER_NSGS_VELOCITY, opts2)
  err = frix_options_bounds(opts2, FRIX_OPT_DRIFT_WINDOW, lower, upper, is_int)
  call check('bounds', err == FRIX_OK .and. lower == 0d0 .and. upper >= 1d6 .and. is_int == 1)
  err = frix_options_set_int(opts2, FRIX_OPT_LOCAL_SOLVER, int(FRIX_LOCAL_NEWTON_AC, c_int64_t))
  call check('local solver by constant', err == FRIX_OK)
  err = frix_options_set_int(opts2, FRIX_OPT_SHUFFLE, int(FRIX_SHUFFLE_ONCE, c_int64_t))
  call check('shuffle by constant', err == FRIX_OK)
  call frix_options_free(opts)
  err = frix_options_copy(opts2, opts)
  err = frix_options_get_int(opts, FRIX_OPT_LOCAL_SOLVER, n64)
  call check('copy', err == FRIX_OK .and. frix_options_solver(opts) == FRIX_SOLVER_NSGS_VELOCITY &
       .and. n64 == FRIX_LOCAL_NEWTON_AC)
  call frix_options_free(opts2)

  ! A Fortran callback stops a solve that would run longer (vi-fpp to 1e-15).
  call frix_options_free(opts)
  err = frix_options_create(FRIX_SOLVER_VI_FPP, opts)
  err = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, 1d-15)
  calls = 0
  err = frix_options_set_callback(opts, c_funloc(stop_at_two), c_loc(calls))
  call check('callback set', err == FRIX_OK)
  r = 0
  err = frix_solve(p, opts, r, u, dummy, info)
  call check('stopped by the callback', err == FRIX_OK .and. calls == 2 .and. &
       frix_info_status(info) == FRIX_STATUS_STOPPED_BY_CALLBACK .and. &
       frix_info_iterations(info) == 2)
  err = frix_options_set_callback(opts, c_null_funptr, c_null_ptr)
  calls = 0
  r = 0
  err = frix_solve(p, opts, r, u, dummy, info)
  call check('callback removed', err == FRIX_OK .and. calls == 0 .and. &
       frix_info_status(info) /= FRIX_STATUS_STOPPED_BY_CALLBACK)

  ! A Fortran log sink receives the progress lines of verbosity 1.
  lines = 0
  err = frix_options_set_log(opts, c_funloc(count_lines), c_loc(lines))
  err = frix_options_set_int(opts, FRIX_OPT_VERBOSITY, 1_c_int64_t)
  r = 0
  err = frix_solve(p, opts, r, u, dummy, info)
  call check('log sink', err == FRIX_OK .and. lines > 0)
  err = frix_options_set_int(opts, FRIX_OPT_VERBOSITY, 0_c_int64_t)
  err = frix_options_set_log(opts, c_null_funptr, c_null_ptr)

  ! Views of the problem's data, and the measures of a given r.
  call c_f_pointer(frix_problem_q(p), view, [3])
  call check('q view', all(view == q))
  call c_f_pointer(frix_problem_mu(p), view, [1])
  call check('mu view', view(1) == mu(1))
  call check('W view', frix_matrix_nnz(frix_problem_W_matrix(p)) == 9)
  call check('no global members', .not. (c_associated(frix_problem_M(p)) .or. &
       c_associated(frix_problem_H(p)) .or. c_associated(frix_problem_f(p)) .or. &
       c_associated(frix_problem_w_vector(p))))
  err = frix_options_set_double(opts, FRIX_OPT_TOLERANCE, 1d-12)
  err = frix_solve(p, opts, r, u, dummy, info)
  u = -1
  err = frix_problem_measure(p, r, dummy, c_loc(u), info)
  err = frix_info_get_double(info, FRIX_INFO_ERROR_RELATIVE, err_value)
  call check('measure', err == FRIX_OK .and. err_value <= 1d-12 .and. &
       abs(u(1) - (4d0 * r(1) + r(2) - 2d0)) < 1d-12)

  ! Block storage: one unsymmetric 3x3 block (column-major 1..9), its diagonal block, the
  ! CSC export and B^T x (B x would give 30, 36, 42).
  err = frix_matrix_from_blocks(1_c_int64_t, 1_c_int64_t, 1_c_int64_t, [0_c_int64_t], &
       [0_c_int64_t], Bd, Wb)
  call check('block matrix', err == FRIX_OK .and. frix_matrix_is_block(Wb) == 1 .and. &
       frix_matrix_block_count(Wb) == 1)
  err = frix_matrix_diagonal_block(Wb, 0_c_int64_t, block)
  call check('diagonal block', err == FRIX_OK .and. all(block == Bd))
  err = frix_matrix_to_csc(Wb, n64, c_null_ptr, c_null_ptr, c_null_ptr)
  call check('CSC size', err == FRIX_OK .and. n64 == 9)
  allocate(csc_colptr(4), csc_rowind(n64), csc_values(n64))
  err = frix_matrix_to_csc(Wb, n64, c_loc(csc_colptr), c_loc(csc_rowind), c_loc(csc_values))
  call check('CSC export', err == FRIX_OK .and. all(csc_colptr == [0, 3, 6, 9]) .and. &
       all(csc_rowind == [0, 1, 2, 0, 1, 2, 0, 1, 2]) .and. all(csc_values == Bd))
  y = 1
  err = frix_matrix_gemv_transposed(Wb, 1d0, [1d0, 2d0, 3d0], 0d0, y)
  call check('B^T x', err == FRIX_OK .and. all(y == [14d0, 32d0, 50d0]))
  call frix_matrix_free(Wb)

  ! FCLIB round trip; optional arrays go through c_loc / c_null_ptr; one guess.
  path = 'test_fortran.hdf5'
  r2 = r + 1
  err = frix_fclib_write(frix_cstr(path), p, c_loc(r), c_loc(u), c_null_ptr, 1_c_int64_t, &
       c_loc(r2), c_loc(u), c_null_ptr)
  call check('FCLIB write', err == FRIX_OK)
  err = frix_fclib_guess_count(frix_cstr(path), n64)
  call check('guess count', err == FRIX_OK .and. n64 == 1)
  err = frix_read_problem(frix_cstr(path), back)
  call check('FCLIB read', err == FRIX_OK .and. frix_problem_contacts(back) == 1)
  r2 = -1
  err = frix_fclib_read_solution(frix_cstr(path), back, c_loc(r2), c_null_ptr, c_null_ptr)
  call check('solution read back', err == FRIX_OK .and. all(r2 == r))
  r2 = 0
  err = frix_fclib_read_guess(frix_cstr(path), back, 0_c_int64_t, c_loc(r2), c_null_ptr, &
       c_null_ptr)
  call check('guess read back', err == FRIX_OK .and. all(r2 == r + 1))
  call frix_problem_free(back)
  err = frix_read_problem(frix_cstr('no/such/file.hdf5'), back)
  call check('missing file', err == FRIX_ERR_IO .and. index(frix_last_error(), 'no/such') > 0)

  ! Degenerate shapes, each written, read back, solved, written with its solution and read
  ! back again: no contacts (local; global with dofs; global with nothing), one contact,
  ! separating, mu = 0, a W with no entries, a W from triplets with duplicates.
  err = frix_problem_local(c_null_ptr, dummy, dummy, 0_c_int64_t, shape)
  call round_trip('no contacts', shape, [0d0], [0d0])
  err = frix_matrix_from_dense(2_c_int64_t, 2_c_int64_t, [2d0, 0d0, 0d0, 4d0], 2_c_int64_t, Ms)
  err = frix_matrix_from_triplets(2_c_int64_t, 0_c_int64_t, 0_c_int64_t, [0_c_int64_t], &
       [0_c_int64_t], dummy, Hs)
  err = frix_problem_global(Ms, Hs, f_two, dummy, dummy, 0_c_int64_t, shape)
  call round_trip('global, dofs and no contacts', shape, [0d0], [0.5d0, -0.5d0])
  call frix_matrix_free(Ms)
  call frix_matrix_free(Hs)
  err = frix_matrix_from_triplets(0_c_int64_t, 0_c_int64_t, 0_c_int64_t, [0_c_int64_t], &
       [0_c_int64_t], dummy, Ms)
  err = frix_matrix_from_triplets(0_c_int64_t, 0_c_int64_t, 0_c_int64_t, [0_c_int64_t], &
       [0_c_int64_t], dummy, Hs)
  err = frix_problem_global(Ms, Hs, dummy, dummy, dummy, 0_c_int64_t, shape)
  call round_trip('global, nothing', shape, [0d0], [0d0])
  call frix_matrix_free(Ms)
  call frix_matrix_free(Hs)
  err = frix_problem_local(W, q_separating, mu, 1_c_int64_t, shape)
  call round_trip('separating', shape, [0d0, 0d0, 0d0], [0d0])
  err = frix_problem_local(W, q, mu_zero, 1_c_int64_t, shape)
  call round_trip('mu = 0', shape, [0.5d0, 0d0, 0d0], [0d0])
  err = frix_matrix_from_triplets(3_c_int64_t, 3_c_int64_t, 0_c_int64_t, [0_c_int64_t], &
       [0_c_int64_t], dummy, Ms)
  err = frix_problem_local(Ms, q_touching, mu, 1_c_int64_t, shape)
  call round_trip('W with no entries', shape, [0d0, 0d0, 0d0], [0d0])
  call frix_matrix_free(Ms)
  ! diag(4, 4, 4) from 2 + 2 at (0,0): r = -q / 4 sticks (|r_T| = 0.13 < 0.4 r_N = 0.2).
  err = frix_matrix_from_triplets(3_c_int64_t, 3_c_int64_t, 4_c_int64_t, &
       [0_c_int64_t, 0_c_int64_t, 1_c_int64_t, 2_c_int64_t], &
       [0_c_int64_t, 0_c_int64_t, 1_c_int64_t, 2_c_int64_t], [2d0, 2d0, 4d0, 4d0], Ms)
  err = frix_problem_local(Ms, q, mu, 1_c_int64_t, shape)
  call round_trip('W from triplets with duplicates', shape, [0.5d0, -0.125d0, -0.025d0], [0d0])
  call frix_matrix_free(Ms)
  ! One contact: the problem above (W dense), its answer known to the solver's tolerance.
  r = 0
  err = frix_solve(p, c_null_ptr, r, u, dummy, info)
  err = frix_problem_local(W, q, mu, 1_c_int64_t, shape)
  call round_trip('one contact', shape, r, [0d0])

  ! Choice options by name: set from text, a name read back, a refusal, and numbers still.
  err = frix_options_create(FRIX_SOLVER_NSGS, opts2)
  err = frix_options_set_by_name(opts2, frix_cstr('shuffle'), frix_cstr('each_sweep'))
  n64 = -1
  if (err == FRIX_OK) err = frix_options_get_int(opts2, FRIX_OPT_SHUFFLE, n64)
  call check('shuffle set by name', err == FRIX_OK .and. n64 == FRIX_SHUFFLE_EACH_SWEEP)
  call check('choice name', frix_fstr(frix_option_choice_name(FRIX_OPT_SHUFFLE, &
       int(FRIX_SHUFFLE_ONCE, c_int64_t))) == 'once' .and. &
       .not. c_associated(frix_option_choice_name(FRIX_OPT_TOLERANCE, 0_c_int64_t)))
  err = frix_option_choice_by_name(FRIX_OPT_ERROR_MEASURE, frix_cstr('siconos'), n64)
  call check('choice by name', err == FRIX_OK .and. n64 == FRIX_MEASURE_RELATIVE)
  err = frix_options_set_by_name(opts2, frix_cstr('shuffle'), frix_cstr('sometimes'))
  call check('unknown choice refused', err == FRIX_ERR_OPTION_RANGE .and. &
       index(frix_last_error(), 'each_sweep') > 0)
  err = frix_options_set_by_name(opts2, frix_cstr('local_solver'), frix_cstr('550'))
  if (err == FRIX_OK) err = frix_options_get_int(opts2, FRIX_OPT_LOCAL_SOLVER, n64)
  call check('choice option set by number text', err == FRIX_OK .and. n64 == FRIX_LOCAL_NEWTON_AC)
  call frix_options_free(opts2)

  call frix_info_free(info)
  call frix_options_free(opts)
  call frix_problem_free(p)
  call frix_matrix_free(W)
  call frix_problem_free(c_null_ptr)
  deallocate(path, csc_colptr, csc_rowind, csc_values)

  print '(i0, " passed, ", i0, " failed")', passed, failures
  if (failures > 0) error stop 1

contains

  ! Writes `prob` (then frees it), reads it back, solves it with the default solver (r from
  ! 0), writes the answer and reads it back. r_exact and v_exact: the answer, to 1e-6.
  subroutine round_trip(what, prob, r_exact, v_exact)
    character(len=*), intent(in) :: what
    type(c_ptr), intent(in) :: prob
    real(c_double), intent(in) :: r_exact(:), v_exact(:)
    type(c_ptr) :: read1, read2, inf
    real(c_double), target :: rs(3), us(3), vs(2), rb(3), ub(3), vb(2)
    real(c_double) :: e
    integer(c_int) :: rc
    integer(c_int64_t) :: m, n
    character(len=*), parameter :: file1 = 'test_fortran_shape.hdf5', file2 = 'test_fortran_shape_sol.hdf5'
    rc = frix_fclib_write(frix_cstr(file1), prob, c_null_ptr, c_null_ptr, c_null_ptr, 0_c_int64_t, &
         c_null_ptr, c_null_ptr, c_null_ptr)
    call check(what // ': write', rc == FRIX_OK)
    rc = frix_read_problem(frix_cstr(file1), read1)
    call check(what // ': read back', rc == FRIX_OK .and. &
         frix_problem_contacts(read1) == frix_problem_contacts(prob) .and. &
         frix_problem_dofs(read1) == frix_problem_dofs(prob))
    call frix_problem_free(prob)
    m = frix_problem_contact_dofs(read1)
    n = frix_problem_dofs(read1)
    rs = 0
    vs = -1
    rc = frix_info_create(inf)
    rc = frix_solve(read1, c_null_ptr, rs, us, vs, inf)
    call check(what // ': solve', rc == FRIX_OK .and. frix_info_status(inf) == FRIX_STATUS_CONVERGED)
    call frix_info_free(inf)
    rc = frix_problem_error(read1, rs, vs, e)
    call check(what // ': error', rc == FRIX_OK .and. e <= 1d-8)
    if (m > 0) call check(what // ': r', all(abs(rs(1:m) - r_exact(1:m)) <= 1d-6))
    if (n > 0) call check(what // ': v', all(abs(vs(1:n) - v_exact(1:n)) <= 1d-6))
    rc = frix_fclib_write(frix_cstr(file2), read1, c_loc(rs), c_loc(us), c_loc(vs), 0_c_int64_t, &
         c_null_ptr, c_null_ptr, c_null_ptr)
    call check(what // ': write the solution', rc == FRIX_OK)
    rc = frix_fclib_read(frix_cstr(file2), read2)
    rb = -7
    ub = -7
    vb = -7
    rc = frix_fclib_read_solution(frix_cstr(file2), read2, c_loc(rb), c_loc(ub), c_loc(vb))
    call check(what // ': read the solution back', rc == FRIX_OK .and. all(rb(1:m) == rs(1:m)) &
         .and. all(ub(1:m) == us(1:m)) .and. all(vb(1:n) == vs(1:n)))
    call frix_problem_free(read2)
    call frix_problem_free(read1)
  end subroutine

  subroutine check(what, ok)
    character(len=*), intent(in) :: what
    logical, intent(in) :: ok
    if (ok) then
      passed = passed + 1
    else
      failures = failures + 1
      print '("FAILED: ", a, " (last frix message: ", a, ")")', what, frix_last_error()
    end if
  end subroutine

end program test_fortran
