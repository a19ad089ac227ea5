! Builds a two-contact local problem u = W r + q from Fortran arrays (W in compressed sparse
! columns, 0-based indices as the C API expects), solves it with NSGS and reports.
! Exit status 0 if the solve converged.
program solve_local
  use, intrinsic :: iso_c_binding
  use frix
  implicit none
  ! W: two contacts, each with a 3x3 diagonal block, coupled through their normals.
  integer(c_int64_t), parameter :: nc = 2, m = 3 * nc
  integer(c_int64_t) :: colptr(m + 1) = [0, 2, 3, 4, 6, 7, 8]
  integer(c_int64_t) :: rowind(8) = [0, 3, 1, 2, 0, 3, 4, 5]
  real(c_double) :: values(8) = [2.0d0, 0.5d0, 1.0d0, 1.0d0, 0.5d0, 2.0d0, 1.0d0, 1.0d0]
  real(c_double) :: q(m) = [-1.0d0, 0.4d0, 0.0d0, -0.5d0, 0.0d0, -0.2d0]
  real(c_double) :: mu(nc) = [0.3d0, 0.5d0]
  real(c_double) :: r(m), u(m), dummy_v(1)
  type(c_ptr) :: W, problem, options, info
  integer(c_int) :: err

  r = 0                                   ! the initial guess
  err = frix_matrix_from_csc(m, m, colptr, rowind, values, W)
  if (err == FRIX_OK) err = frix_problem_local(W, q, mu, nc, problem)
  if (err == FRIX_OK) err = frix_options_create(FRIX_SOLVER_NSGS, options)
  if (err == FRIX_OK) err = frix_options_set_double(options, FRIX_OPT_TOLERANCE, 1.0d-12)
  if (err == FRIX_OK) err = frix_info_create(info)
  if (err == FRIX_OK) err = frix_solve(problem, options, r, u, dummy_v, info)
  if (err /= FRIX_OK) then
    print '(a, a)', 'frix: ', frix_last_error()
    stop 1
  end if

  print '(a, " in ", i0, " iterations, error ", es9.2)', &
       frix_fstr(frix_status_string(frix_info_status(info))), frix_info_iterations(info), &
       frix_info_error(info)
  print '("r = ", 6f10.5)', r
  print '("u = ", 6f10.5)', u
  err = frix_info_status(info)

  call frix_info_free(info)
  call frix_options_free(options)
  call frix_problem_free(problem)
  call frix_matrix_free(W)
  if (err /= FRIX_STATUS_CONVERGED) stop 1
end program solve_local
