! bw_reference's solver: the mixed problem of model.md in quadruple
! precision (real128), written from model.md without blockwall's kernels,
! to measure the forward error of blockwall's double-precision results.
!
! Derivation, per interface k (blocks i, j; centre G; t = (cos th, sin th),
! n = (-sin th, cos th); length l; depth s; m portions):
!   a material point x of block b moves by u_b(x) = (u1 - w (x2-c2), u2 + w (x1-c1));
!   portion p has midpoint P_p = G + x_p t, x_p = -l/2 + (p-1/2) l/m, area A_p = s l/m;
!   the jump [[u]](P) = u_j(P) - u_i(P) is linear in (q_i, q_j), so
!     dt_p = t . [[u]](P_p) = a_p . (q_i, q_j),  dn_p = n . [[u]](P_p) = b_p . (q_i, q_j)
!   compatibility (weighted by A_p, exact since dn is linear along the
!   interface):  A_p rt_p / kt = A_p dt_p,  A_p rn_p / kn = A_p dn_p,
!   i.e. the rows of D are A_p a_p and A_p b_p and G = diag(A_p/kt, A_p/kn);
!   equilibrium (virtual work): D^T r = F on the free dofs.
! Eliminating r = G^-1 D q (exact: G is diagonal) gives the condensed stiffness
!     K = sum_k sum_p A_p (kt a_p a_p^T + kn b_p b_p^T),   K q = F,
! assembled here portion by portion (not from blockwall's closed form
! diag(kt A, kn A, kn I (1-1/m^2))), factored by a skyline (variable band)
! Cholesky in real128 and improved by iterative refinement in real128; then
! r = G^-1 D q. Prescribed dofs are zero (bw_reference's input has no
! prescribed values). With eps_128 = 1.9e-34, the reference's own error is
! about cond(K) * eps_128 * n, far below any double-precision error while
! cond(K) < 1e25; it is reported so that a test can check it.
! The limit m -> infinity (exact = 1) replaces the m portions by the exact
! integral over the interface, two-point Gauss-Legendre (the integrand is
! quadratic in x), i.e. the exact interface stiffness diag(kt A, kn A, kn I).
!
! Error measures of a double-precision solution (q_f, r_f), all in real128:
!   the scaled norm blockwall uses (README "How the answer is checked"):
!     r~ = G^1/2 r, q~ = diag(K)^1/2 q, S^ = diag(K)^-1/2 K diag(K)^-1/2 = D^T D^,
!     K~ = [-I D^; D^T 0] (fields r, q);
!   relative forward errors: translations, rotations, stresses (max norms,
!   each relative to the largest reference value of its kind), and the
!   2-norm of x~ = (r~, q~);
!   the true residual ||b~ - K~ x~_f|| / ||b~||, b~ = (0, diag(K)^-1/2 F);
!   the condition number of K~ from the extreme eigenvalues of S^
!   (sigma^2 of D^): K~ has eigenvalues (-1 +- sqrt(1 + 4 sigma^2))/2 and
!   -1 on the orthogonal complement of range(D^); the extreme eigenvalues
!   come from 30 steps of power and of inverse iteration (Rayleigh
!   quotients: the estimate is a lower bound; 2 % below that of 60 steps
!   on a 1e3-block wall).
module bw_reference_solver
  use, intrinsic :: iso_c_binding, only: c_double, c_int, c_int64_t, c_int8_t
  use, intrinsic :: iso_fortran_env, only: real128
  implicit none
  private
  public :: bw_reference_solve

  integer, parameter :: qp = real128
  ! entries of stats(:), see bw_reference_solve
  integer, parameter, public :: NSTATS = 22

  integer(c_int), parameter :: OK = 0, ERR_NOT_SPD = 1, ERR_TOO_LARGE = 2, ERR_INPUT = 3

  type :: skyline
    integer :: n = 0
    integer, allocatable :: first(:)      ! first stored column of each row
    integer(c_int64_t), allocatable :: ptr(:)  ! offset of row i's first entry
    real(qp), allocatable :: v(:)
  end type skyline

contains

  ! The derivatives a (of dt) and b (of dn) at point P with respect to
  ! (u1, u2, w)_i, (u1, u2, w)_j.
  pure subroutine jump_rows(ci, cj, p, t, n, a, b)
    real(qp), intent(in) :: ci(2), cj(2), p(2), t(2), n(2)
    real(qp), intent(out) :: a(6), b(6)
    real(qp) :: ui(2, 3), uj(2, 3)
    integer :: c
    ! u_b(P) = U(:, 1) u1 + U(:, 2) u2 + U(:, 3) w
    ui = reshape([1.0_qp, 0.0_qp, 0.0_qp, 1.0_qp, -(p(2) - ci(2)), p(1) - ci(1)], [2, 3])
    uj = reshape([1.0_qp, 0.0_qp, 0.0_qp, 1.0_qp, -(p(2) - cj(2)), p(1) - cj(1)], [2, 3])
    do c = 1, 3
      a(c) = -dot_product(t, ui(:, c))
      b(c) = -dot_product(n, ui(:, c))
      a(3 + c) = dot_product(t, uj(:, c))
      b(3 + c) = dot_product(n, uj(:, c))
    end do
  end subroutine jump_rows

  pure subroutine interface_frame(theta, t, n)
    real(c_double), intent(in) :: theta
    real(qp), intent(out) :: t(2), n(2)
    t = [cos(real(theta, qp)), sin(real(theta, qp))]
    n = [-t(2), t(1)]
  end subroutine interface_frame

  pure function entry_index(k, i, j) result(e)
    type(skyline), intent(in) :: k
    integer, intent(in) :: i, j
    integer(c_int64_t) :: e
    e = k%ptr(i) + (j - k%first(i))
  end function entry_index

  ! y = K x for the symmetric skyline matrix (lower triangle stored).
  pure subroutine sky_mult(k, x, y)
    type(skyline), intent(in) :: k
    real(qp), intent(in) :: x(:)
    real(qp), intent(out) :: y(:)
    integer :: i, j
    integer(c_int64_t) :: e
    y = 0
    do i = 1, k%n
      do j = k%first(i), i
        e = entry_index(k, i, j)
        y(i) = y(i) + k%v(e) * x(j)
        if (j /= i) y(j) = y(j) + k%v(e) * x(i)
      end do
    end do
  end subroutine sky_mult

  ! In-place Cholesky K = L L^T of the skyline (row-oriented: the profile of
  ! L is that of K). Fails on a non-positive pivot (a mechanism).
  pure subroutine sky_cholesky(k, status)
    type(skyline), intent(inout) :: k
    integer(c_int), intent(out) :: status
    integer :: i, j, lo, c
    integer(c_int64_t) :: ei, ej
    real(qp) :: s
    status = OK
    do i = 1, k%n
      do j = k%first(i), i
        lo = max(k%first(i), k%first(j))
        ei = entry_index(k, i, lo)
        ej = entry_index(k, j, lo)
        s = k%v(entry_index(k, i, j))
        do c = 0, j - lo - 1
          s = s - k%v(ei + c) * k%v(ej + c)
        end do
        if (j < i) then
          k%v(entry_index(k, i, j)) = s / k%v(entry_index(k, j, j))
        else
          if (.not. (s > 0)) then
            status = ERR_NOT_SPD
            return
          end if
          k%v(entry_index(k, i, i)) = sqrt(s)
        end if
      end do
    end do
  end subroutine sky_cholesky

  ! Solve L L^T x = b with the factor from sky_cholesky.
  pure subroutine sky_solve(l, b, x)
    type(skyline), intent(in) :: l
    real(qp), intent(in) :: b(:)
    real(qp), intent(out) :: x(:)
    integer :: i, j
    x = b
    do i = 1, l%n
      do j = l%first(i), i - 1
        x(i) = x(i) - l%v(entry_index(l, i, j)) * x(j)
      end do
      x(i) = x(i) / l%v(entry_index(l, i, i))
    end do
    do i = l%n, 1, -1
      x(i) = x(i) / l%v(entry_index(l, i, i))
      do j = l%first(i), i - 1
        x(j) = x(j) - l%v(entry_index(l, i, j)) * x(i)
      end do
    end do
  end subroutine sky_solve

  !> Solve the problem of a blockwall output file in real128 and measure a
  !! double-precision solution against it.
  !!
  !! In (C row-major shapes): centroid[nb][2], prescribed[nb][3] (1 = fixed at 0),
  !! load[nb][3], pairs[ni][2] (0-based), center[ni][2], angle, length, kn, kt [ni];
  !! with have_file /= 0 the solution to measure: q_file[nb][3] and, with
  !! have_stress /= 0, s_file[ni][m][2] (shear, normal per portion).
  !! With exact /= 0 the reference is the limit m -> infinity (the exact
  !! interface stiffness diag(kt A, kn A, kn I), model.md): its stresses are the
  !! linear field sigma(x) at the file's m portion midpoints.
  !! Out: q_ref[nb][3], s_ref[ni][m][2], f_ref[ni][3] (T, N, M), g_ref[ni][3]
  !! (dt, dn, phi at G), and stats:
  !!   1 free dofs, 2 lambda_min(S^), 3 lambda_max(S^), 4 cond(S^), 5 cond(K~),
  !!   6 size of the last refinement correction (scaled, relative),
  !!   7 relative residual of K q = F after refinement (scaled),
  !!   8 error of translations, 9 of rotations, 10 of stresses (max norms),
  !!   11 error of x~ (2-norm, relative), 12 of q~, 13 of r~,
  !!   14 true residual of the file's solution, full scaled system (blockwall's definition),
  !!   15 its equilibrium rows ||D^T r - F||~ / ||F||~, 16 its compatibility rows ||D q - G r||~ / ||D q||~,
  !!   17 plain relative residual of the unscaled mixed system (illustration only),
  !!   18 steps of inverse iteration for lambda_min, 19 entries of the skyline,
  !!   20 bound on the reference's own relative error, cond(S^) * n * eps_128 * 10,
  !!   21 ||x~|| / ||b~|| of the reference solution: a residual computed in double
  !!      cannot fall below about eps_64 times this (cancellation in b~ - K~ x~),
  !!   22 normwise backward error of the file's solution,
  !!      ||b~ - K~ x~|| / (||K~||_2 ||x~|| + ||b~||) (Rigal and Gaches).
  subroutine bw_reference_solve(nb, ni, m, exact, depth, centroid, prescribed, load, pairs, center, angle, length, kn, kt, &
       have_file, have_stress, q_file, s_file, q_ref, s_ref, f_ref, g_ref, stats, status) bind(C, name="bw_reference_solve")
    integer(c_int), value, intent(in) :: nb, ni, m, exact, have_file, have_stress
    real(c_double), value, intent(in) :: depth
    real(c_double), intent(in) :: centroid(2, nb), load(3, nb), center(2, ni), angle(ni), length(ni), kn(ni), kt(ni)
    integer(c_int8_t), intent(in) :: prescribed(3, nb)
    integer(c_int64_t), intent(in) :: pairs(2, ni)
    real(c_double), intent(in) :: q_file(3, nb), s_file(2, m, ni)
    real(c_double), intent(out) :: q_ref(3, nb), s_ref(2, m, ni), f_ref(3, ni), g_ref(3, ni), stats(NSTATS)
    integer(c_int), intent(out) :: status

    type(skyline) :: kmat, lfac
    integer, allocatable :: dof(:)
    real(qp), allocatable :: f(:), q(:), res(:), dq(:), dscale(:), qfull(:, :), x(:), y(:)
    real(qp) :: t(2), n(2), ci(2), cj(2), gc(2), pt(2), a(6), b(6), ap, xp, kloc(6, 6)
    real(qp) :: lmin, lmax, sigmax, sigmin, mu_max, mu_min, rq, corr
    integer :: nfree, k, p, c, r, bi, bj, cols(6), i, j, it, nit
    integer(c_int64_t) :: total

    stats = 0
    g_ref = 0
    q_ref = 0
    s_ref = 0
    f_ref = 0
    status = OK
    if (m < 1 .or. nb < 1 .or. .not. (depth > 0)) then
      status = ERR_INPUT
      return
    end if
    do k = 1, ni
      if (.not. (length(k) > 0 .and. kn(k) > 0 .and. kt(k) > 0) .or. any(pairs(:, k) < 0) .or. any(pairs(:, k) >= nb)) then
        status = ERR_INPUT
        return
      end if
    end do

    ! 1. free dofs, numbered block by block
    allocate(dof(3 * nb))
    nfree = 0
    do i = 1, nb
      do c = 1, 3
        if (prescribed(c, i) /= 0) then
          dof(3 * (i - 1) + c) = 0
        else
          nfree = nfree + 1
          dof(3 * (i - 1) + c) = nfree
        end if
      end do
    end do
    stats(1) = nfree
    if (nfree == 0) then
      status = ERR_INPUT
      return
    end if

    ! 2. profile: the first column coupled to each row (same block, or a
    ! block across an interface)
    kmat%n = nfree
    allocate(kmat%first(nfree), kmat%ptr(nfree))
    do i = 1, nfree
      kmat%first(i) = i
    end do
    do i = 1, nb
      call couple(i, i)
    end do
    do k = 1, ni
      call couple(int(pairs(1, k)) + 1, int(pairs(2, k)) + 1)
    end do
    total = 0
    do i = 1, nfree
      kmat%ptr(i) = total + 1
      total = total + (i - kmat%first(i) + 1)
    end do
    stats(19) = real(total, c_double)
    ! 16 bytes each, twice (K and its factor): keep below ~1.6 GB
    if (total > 50000000_c_int64_t) then
      status = ERR_TOO_LARGE
      return
    end if
    allocate(kmat%v(total))
    kmat%v = 0

    ! 3. K = sum over portions of A_p (kt a a^T + kn b b^T), and F
    do k = 1, ni
      bi = int(pairs(1, k)) + 1
      bj = int(pairs(2, k)) + 1
      call interface_frame(angle(k), t, n)
      ci = real(centroid(:, bi), qp)
      cj = real(centroid(:, bj), qp)
      gc = real(center(:, k), qp)
      kloc = 0
      if (exact /= 0) then
        ! m = infinity: the integral over the interface, by two-point
        ! Gauss-Legendre, exact for the quadratic integrand (dn is linear)
        ap = real(depth, qp) * real(length(k), qp) / 2
        do p = 1, 2
          xp = real(length(k), qp) / 2 * merge(-1, 1, p == 1) / sqrt(3.0_qp)
          pt = gc + xp * t
          call jump_rows(ci, cj, pt, t, n, a, b)
          do c = 1, 6
            kloc(:, c) = kloc(:, c) + ap * (real(kt(k), qp) * a * a(c) + real(kn(k), qp) * b * b(c))
          end do
        end do
      else
        ap = real(depth, qp) * real(length(k), qp) / m
        do p = 1, m
          xp = real(length(k), qp) * ((p - 0.5_qp) / m - 0.5_qp)
          pt = gc + xp * t
          call jump_rows(ci, cj, pt, t, n, a, b)
          do c = 1, 6
            kloc(:, c) = kloc(:, c) + ap * (real(kt(k), qp) * a * a(c) + real(kn(k), qp) * b * b(c))
          end do
        end do
      end if
      cols(1:3) = dof(3 * (bi - 1) + 1:3 * bi)
      cols(4:6) = dof(3 * (bj - 1) + 1:3 * bj)
      do c = 1, 6
        do r = 1, 6
          i = cols(r)
          j = cols(c)
          if (i == 0 .or. j == 0 .or. j > i) cycle
          kmat%v(entry_index(kmat, i, j)) = kmat%v(entry_index(kmat, i, j)) + kloc(r, c)
        end do
      end do
    end do
    allocate(f(nfree), q(nfree), res(nfree), dq(nfree), dscale(nfree), x(nfree), y(nfree))
    do i = 1, nb
      do c = 1, 3
        if (dof(3 * (i - 1) + c) > 0) f(dof(3 * (i - 1) + c)) = real(load(c, i), qp)
      end do
    end do
    do i = 1, nfree
      dscale(i) = sqrt(kmat%v(entry_index(kmat, i, i)))
      if (.not. (dscale(i) > 0)) then
        status = ERR_NOT_SPD
        return
      end if
    end do

    ! 4. factor, solve, refine (residuals in real128 against the stored K)
    lfac = kmat
    call sky_cholesky(lfac, status)
    if (status /= OK) return
    call sky_solve(lfac, f, q)
    corr = 0
    do it = 1, 3
      call sky_mult(kmat, q, res)
      res = f - res
      call sky_solve(lfac, res, dq)
      q = q + dq
      corr = scaled_norm(dq) / max(scaled_norm(q), tiny(1.0_qp))
    end do
    call sky_mult(kmat, q, res)
    stats(6) = real(corr, c_double)
    stats(7) = real(norm2((f - res) / dscale) / max(norm2(f / dscale), tiny(1.0_qp)), c_double)

    ! 5. extreme eigenvalues of S^ = Ds^-1 K Ds^-1 (power and inverse
    ! iteration from a fixed, non-symmetric start; Rayleigh quotients)
    nit = 30
    x = [(1.0_qp + 0.1_qp * sin(real(i, qp)), i = 1, nfree)]
    x = x / norm2(x)
    lmax = 0
    do it = 1, nit
      call sky_mult(kmat, x / dscale, y)
      y = y / dscale
      lmax = dot_product(x, y)
      x = y / norm2(y)
    end do
    x = [(1.0_qp + 0.1_qp * cos(real(i, qp)), i = 1, nfree)]
    x = x / norm2(x)
    lmin = huge(1.0_qp)
    do it = 1, nit
      call sky_solve(lfac, x * dscale, y)
      y = y * dscale
      rq = dot_product(x, y)
      lmin = 1 / rq
      x = y / norm2(y)
    end do
    stats(2) = real(lmin, c_double)
    stats(3) = real(lmax, c_double)
    stats(4) = real(lmax / lmin, c_double)
    sigmax = sqrt(lmax)
    sigmin = sqrt(lmin)
    mu_max = (1 + sqrt(1 + 4 * sigmax**2)) / 2
    mu_min = min(1.0_qp, (sqrt(1 + 4 * sigmin**2) - 1) / 2)
    stats(5) = real(mu_max / mu_min, c_double)
    stats(18) = nit
    stats(20) = real(lmax / lmin * nfree * epsilon(1.0_qp) * 10, c_double)

    ! 6. reference results: q, r = G^-1 D q, resultants H r
    allocate(qfull(3, nb))
    qfull = 0
    do i = 1, nb
      do c = 1, 3
        if (dof(3 * (i - 1) + c) > 0) qfull(c, i) = q(dof(3 * (i - 1) + c))
      end do
    end do
    q_ref = real(qfull, c_double)
    call stresses_and_errors()

  contains

    subroutine couple(b1, b2)
      integer, intent(in) :: b1, b2
      integer :: c1, c2, d1, d2
      do c1 = 1, 3
        do c2 = 1, 3
          d1 = dof(3 * (b1 - 1) + c1)
          d2 = dof(3 * (b2 - 1) + c2)
          if (d1 == 0 .or. d2 == 0) cycle
          kmat%first(max(d1, d2)) = min(kmat%first(max(d1, d2)), min(d1, d2))
        end do
      end do
    end subroutine couple

    pure function scaled_norm(v) result(s)
      real(qp), intent(in) :: v(:)
      real(qp) :: s
      s = norm2(v * dscale)
    end function scaled_norm

    ! Reference stresses and resultants; with a file solution, its errors
    ! and its true residual, all in real128.
    subroutine stresses_and_errors()
      real(qp) :: rt, rn, ff(3), g1, g2, dtf, dnf, rtf, rnf
      real(qp) :: e_r2, n_r2, e_q2, n_q2, res_r2, dq_r2, res_q2, f2, ures2, ub2
      real(qp) :: e_s, n_s, e_u, n_u, e_w, n_w
      real(qp), allocatable :: qf(:, :), dtr(:)
      integer :: kk, pp, bb, cc
      allocate(qf(3, nb), dtr(nfree))
      qf = 0
      if (have_file /= 0) qf = real(q_file, qp)
      do bb = 1, nb
        do cc = 1, 3
          if (dof(3 * (bb - 1) + cc) == 0) qf(cc, bb) = 0
        end do
      end do
      e_r2 = 0; n_r2 = 0; res_r2 = 0; dq_r2 = 0; e_s = 0; n_s = 0; ures2 = 0
      dtr = 0
      do kk = 1, ni
        bi = int(pairs(1, kk)) + 1
        bj = int(pairs(2, kk)) + 1
        call interface_frame(angle(kk), t, n)
        ci = real(centroid(:, bi), qp)
        cj = real(centroid(:, bj), qp)
        gc = real(center(:, kk), qp)
        ap = real(depth, qp) * real(length(kk), qp) / m
        g1 = ap / real(kt(kk), qp)
        g2 = ap / real(kn(kk), qp)
        ff = 0
        call jump_rows(ci, cj, gc, t, n, a, b)
        g_ref(:, kk) = real([dot_product(a(1:3), qfull(:, bi)) + dot_product(a(4:6), qfull(:, bj)), &
                             dot_product(b(1:3), qfull(:, bi)) + dot_product(b(4:6), qfull(:, bj)), &
                             qfull(3, bj) - qfull(3, bi)], c_double)
        do pp = 1, m
          xp = real(length(kk), qp) * ((pp - 0.5_qp) / m - 0.5_qp)
          pt = gc + xp * t
          call jump_rows(ci, cj, pt, t, n, a, b)
          rt = real(kt(kk), qp) * (dot_product(a(1:3), qfull(:, bi)) + dot_product(a(4:6), qfull(:, bj)))
          rn = real(kn(kk), qp) * (dot_product(b(1:3), qfull(:, bi)) + dot_product(b(4:6), qfull(:, bj)))
          s_ref(:, pp, kk) = real([rt, rn], c_double)
          ff = ff + ap * [rt, rn, xp * rn]
          n_s = max(n_s, abs(rt), abs(rn))
          n_r2 = n_r2 + g1 * rt**2 + g2 * rn**2
          if (have_file == 0) cycle
          ! the file's solution: compatibility rows and D^T r
          dtf = dot_product(a(1:3), qf(:, bi)) + dot_product(a(4:6), qf(:, bj))
          dnf = dot_product(b(1:3), qf(:, bi)) + dot_product(b(4:6), qf(:, bj))
          if (have_stress /= 0) then
            rtf = real(s_file(1, pp, kk), qp)
            rnf = real(s_file(2, pp, kk), qp)
          else
            ! no stresses in the file: those of its displacements
            rtf = real(kt(kk), qp) * dtf
            rnf = real(kn(kk), qp) * dnf
          end if
          e_s = max(e_s, abs(rtf - rt), abs(rnf - rn))
          e_r2 = e_r2 + g1 * (rtf - rt)**2 + g2 * (rnf - rn)**2
          ! row of r~: b - K~x = r~ - D^ q~ = G^1/2 r - G^-1/2 D q, D q = A_p (dt, dn)
          res_r2 = res_r2 + (sqrt(g1) * rtf - ap * dtf / sqrt(g1))**2 + (sqrt(g2) * rnf - ap * dnf / sqrt(g2))**2
          dq_r2 = dq_r2 + (ap * dtf)**2 / g1 + (ap * dnf)**2 / g2
          ures2 = ures2 + (g1 * rtf - ap * dtf)**2 + (g2 * rnf - ap * dnf)**2
          do cc = 1, 6
            bb = merge(bi, bj, cc <= 3)
            i = dof(3 * (bb - 1) + mod(cc - 1, 3) + 1)
            if (i > 0) dtr(i) = dtr(i) + ap * (a(cc) * rtf + b(cc) * rnf)
          end do
        end do
        f_ref(:, kk) = real(ff, c_double)
      end do
      n_q2 = norm2(q * dscale)**2
      stats(21) = real(sqrt((n_r2 + n_q2) / max(norm2(f / dscale)**2, tiny(1.0_qp))), c_double)
      if (have_file == 0) return
      e_q2 = norm2((real(pack_free(qf), qp) - q) * dscale)**2
      res_q2 = norm2((f - dtr) / dscale)**2
      f2 = norm2(f / dscale)**2
      ub2 = norm2(f)**2
      e_u = 0; n_u = 0; e_w = 0; n_w = 0
      do bb = 1, nb
        e_u = max(e_u, maxval(abs(qf(1:2, bb) - qfull(1:2, bb))))
        n_u = max(n_u, maxval(abs(qfull(1:2, bb))))
        e_w = max(e_w, abs(qf(3, bb) - qfull(3, bb)))
        n_w = max(n_w, abs(qfull(3, bb)))
      end do
      stats(8) = real(e_u / max(n_u, tiny(1.0_qp)), c_double)
      stats(9) = real(e_w / max(n_w, tiny(1.0_qp)), c_double)
      stats(10) = real(e_s / max(n_s, tiny(1.0_qp)), c_double)
      stats(11) = real(sqrt((e_r2 + e_q2) / max(n_r2 + n_q2, tiny(1.0_qp))), c_double)
      stats(12) = real(sqrt(e_q2 / max(n_q2, tiny(1.0_qp))), c_double)
      stats(13) = real(sqrt(e_r2 / max(n_r2, tiny(1.0_qp))), c_double)
      stats(14) = real(sqrt((res_r2 + res_q2) / max(f2, tiny(1.0_qp))), c_double)
      stats(15) = real(sqrt(res_q2 / max(f2, tiny(1.0_qp))), c_double)
      stats(16) = real(sqrt(res_r2 / max(dq_r2, tiny(1.0_qp))), c_double)
      stats(17) = real(sqrt((ures2 + norm2(f - dtr)**2) / max(ub2, tiny(1.0_qp))), c_double)
      stats(22) = real(sqrt(res_r2 + res_q2) / (mu_max * sqrt(n_r2 + n_q2) + sqrt(f2)), c_double)
    end subroutine stresses_and_errors

    pure function pack_free(v) result(w)
      real(qp), intent(in) :: v(:, :)
      real(qp) :: w(nfree)
      integer :: bb, cc
      do bb = 1, nb
        do cc = 1, 3
          if (dof(3 * (bb - 1) + cc) > 0) w(dof(3 * (bb - 1) + cc)) = v(cc, bb)
        end do
      end do
    end function pack_free

  end subroutine bw_reference_solve

end module bw_reference_solver
