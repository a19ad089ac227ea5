! The Fortran binding (include/frix/frix.f90) end to end: constants, strings both ways,
! errors with messages, matrices, a solve checked by an independent error, options, and an
! FCLIB round trip through c_loc. Prints one line per check; exits non-zero on a failure.
program test_fortran
  use, intrinsic :: iso_c_binding
  use frix
  implicit none
  integer :: failures = 0, passed = 0
  real(c_double), target :: Wd(9) = [4d0, 1d0, 0d0, 1d0, 3d0, 0d0, 0d0, 0d0, 3d0]
  real(c_double), target :: q(3) = [-2d0, 0.5d0, 0.1d0], mu(1) = [0.4d0]
  real(c_double), target :: r(3), u(3), r2(3), dummy(1)
  real(c_double) :: err_value, tol
  integer(c_int64_t) :: n64
  integer(c_int) :: err, id
  type(c_ptr) :: W, p, back, opts, info
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

  ! The default solver (auto): its trace, and the existence check.
  r = 0
  err = frix_solve(p, c_null_ptr, r, u, dummy, info)
  err = frix_info_get_int(info, FRIX_INFO_SOLVER_ID, n64)
  call check('default solver is auto', err == FRIX_OK .and. n64 == FRIX_SOLVER_AUTO)
  call check('auto trace', index(frix_fstr(frix_info_trace(info)), 'analysis:') == 1)
  err = frix_problem_check_existence(p, 0d0, info)
  err = frix_info_get_int(info, FRIX_INFO_EXISTENCE, n64)
  call check('existence', err == FRIX_OK .and. n64 == FRIX_EXISTENCE_GUARANTEED .and. &
       frix_fstr(frix_existence_describe(int(n64, c_int))) == 'a solution exists')

  ! FCLIB round trip; optional arrays go through c_loc / c_null_ptr.
  path = 'test_fortran.hdf5'
  err = frix_fclib_write(frix_cstr(path), p, c_loc(r), c_loc(u), c_null_ptr, 0_c_int64_t, &
       c_null_ptr, c_null_ptr, c_null_ptr)
  call check('FCLIB write', err == FRIX_OK)
  err = frix_read_problem(frix_cstr(path), back)
  call check('FCLIB read', err == FRIX_OK .and. frix_problem_contacts(back) == 1)
  r2 = -1
  err = frix_fclib_read_solution(frix_cstr(path), back, c_loc(r2), c_null_ptr, c_null_ptr)
  call check('solution read back', err == FRIX_OK .and. all(r2 == r))
  call frix_problem_free(back)
  err = frix_read_problem(frix_cstr('no/such/file.hdf5'), back)
  call check('missing file', err == FRIX_ERR_IO .and. index(frix_last_error(), 'no/such') > 0)

  call frix_info_free(info)
  call frix_options_free(opts)
  call frix_problem_free(p)
  call frix_matrix_free(W)
  call frix_problem_free(c_null_ptr)
  deallocate(path)

  print '(i0, " passed, ", i0, " failed")', passed, failures
  if (failures > 0) error stop 1

contains

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
