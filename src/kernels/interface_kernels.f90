! Per-interface kernels of the mixed rigid-block model (model.md, paper eq.
! 14-28, and its section "Three dimensions"), written once for both
! dimensions.
!
! The three-dimensional objects are the general ones. An interface joins
! block i (first) to block j (second) across a plane polygon with centre G
! and local frame (t, n, b), rows of Q, n from i into j. A block's dofs are
! q = (u1, u2, u3, w1, w2, w3); the relative displacement at G, local axes,
! dG = (dt, dn, db, phit, phin, phib) = R B q with
!   B = [-P_i, P_j],  P_b = [[I, -[G - c_b]x], [0, I]],  R = diag(Q, Q).
! A portion p (area A_p, centroid (xi_p, eta_p) from G along t and b)
! carries r_p = (rt, rn, rb) and sees the jump j_p = E_p dG,
!   E_p = [[1, 0, 0,    0,   eta,  0],
!          [0, 1, 0, -eta,     0, xi],
!          [0, 0, 1,    0,   -xi,  0]],
! H r = sum_p A_p E_p^T r_p = (T, N, Tb, Mt, Mn, Mb), K_G = sum_p A_p E_p^T
! C_p E_p, the pair's stiffness (R B)^T K_G (R B), and the rows of D^,
! sqrt(A_p) C^1/2 E_p R B with C = diag(kt, kn, kt).
!
! Two dimensions are the same objects restricted (dim = 2): the dofs
! (u1, u2, w3), the components (dt, dn, phib) of dG and (rt, rn) of r, the
! frame t = (cos th, sin th, 0), n = (-sin th, cos th, 0), b = X3, and the
! portions in one row (eta = 0), so that E_p = [[1, 0, 0], [0, 1, xi_p]]:
! exactly the paper's 2D kernels, since with eta = 0 and b = X3 the terms
! the restriction drops are zero. nd = 3 or 6 dofs per block, nr = 3 or 6
! components of dG, ns = 2 or 3 stress components.
!
! The portion map E_p, its transpose H, and the portions of a rectangle
! are defined here and nowhere else: the assembled and the shell forms of
! D^, the jumps a joint law sees and the resultants written all come from
! these procedures.
!
! Every procedure is a pure subroutine, data in and data out, whose last
! argument is the status (a pure function may not write its arguments);
! none stops or prints: the caller (C, through include/blockwall/kernels.h)
! owns error reporting. Arrays are passed so that C sees them row-major:
! the Fortran array k(n, n) is the C array double k[n][n] with k[a][b] =
! k(b, a). Lever arms G - c are formed here from the coordinates given;
! callers that work far from the origin pass coordinates relative to a
! nearby point.
module bw_interface_kernels
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  implicit none
  private
  public :: bw_kernel_frame, bw_kernel_rectangle_portions, bw_kernel_compatibility, bw_kernel_jumps, &
            bw_kernel_resultants, bw_kernel_condense, bw_kernel_stiffness, bw_kernel_operator, &
            bw_kernel_jumps_abs, bw_kernel_resultants_abs, bw_kernel_jumps_dd, bw_kernel_resultants_dd
  public :: bw_interface_compatibility, bw_interface_jumps, bw_interface_resultants, &
            bw_interface_condense, bw_interface_stiffness, bw_interface_operator

  integer(c_int), parameter, public :: BW_KERNEL_OK = 0, BW_KERNEL_BAD_M = 1, &
       BW_KERNEL_BAD_LENGTH = 2, BW_KERNEL_BAD_DEPTH = 3, BW_KERNEL_BAD_STIFFNESS = 4, &
       BW_KERNEL_BAD_DIMENSION = 5, BW_KERNEL_BAD_FRAME = 6

  ! the 2D components within the 3D ones: dofs and dG (u1, u2, w3) and
  ! (dt, dn, phib) (the stresses (rt, rn) are the first two)
  integer, parameter :: KEEP2(3) = [1, 2, 6]

contains

  ! ---------------------------------------------------------------- helpers

  pure function dofs(dim) result(nd)
    integer(c_int), intent(in) :: dim
    integer :: nd
    nd = merge(6, 3, dim == 3)
  end function dofs

  pure function stresses(dim) result(ns)
    integer(c_int), intent(in) :: dim
    integer :: ns
    ns = merge(3, 2, dim == 3)
  end function stresses

  ! index in the 3D components of the a-th dof (or dG component) of dim
  pure function dof_index(dim, a) result(k)
    integer(c_int), intent(in) :: dim
    integer, intent(in) :: a
    integer :: k
    if (dim == 3) then
      k = a
    else
      k = KEEP2(a)
    end if
  end function dof_index

  ! The comparisons are written so that NaN fails them.
  pure function check_portions(dim, np, area) result(status)
    integer(c_int), intent(in) :: dim, np
    real(c_double), intent(in) :: area(:)
    integer(c_int) :: status
    status = BW_KERNEL_OK
    if (dim /= 2 .and. dim /= 3) then
      status = BW_KERNEL_BAD_DIMENSION
    else if (np < 1) then
      status = BW_KERNEL_BAD_M
    else if (.not. all(area > 0 .and. area < huge(area))) then
      status = BW_KERNEL_BAD_LENGTH
    end if
  end function check_portions

  ! a dimension and a count of portions the jump kernels take
  pure function check_jumps(dim, np) result(status)
    integer(c_int), intent(in) :: dim, np
    integer(c_int) :: status
    status = BW_KERNEL_OK
    if (dim /= 2 .and. dim /= 3) then
      status = BW_KERNEL_BAD_DIMENSION
    else if (np < 1) then
      status = BW_KERNEL_BAD_M
    end if
  end function check_jumps

  ! E_p (3 x 6) of a portion at (xi, eta)
  pure function portion_map(xi, eta) result(e)
    real(c_double), intent(in) :: xi, eta
    real(c_double) :: e(3, 6)
    e = 0
    e(1, 1) = 1
    e(2, 2) = 1
    e(3, 3) = 1
    e(1, 5) = eta
    e(2, 4) = -eta
    e(2, 6) = xi
    e(3, 5) = -xi
  end function portion_map

  ! ------------------------------------------------------- general kernels

  !> The local frame of an interface with unit normal n (C: double
  !! frame[3][3], rows t, n, b): b = X3 projected onto the interface plane,
  !! or X2 when that projection is shorter than 1e-6; t = n x b. In 2D
  !! (n in the X1-X2 plane) b = X3 and t = (n2, -n1, 0).
  pure subroutine bw_kernel_frame(normal, frame, status) bind(C, name="bw_kernel_frame")
    real(c_double), intent(in) :: normal(3)
    real(c_double), intent(out) :: frame(3, 3)
    integer(c_int), intent(out) :: status
    real(c_double) :: n(3), b(3), t(3), len
    frame = 0
    len = norm2(normal)
    if (.not. (len > 0 .and. len < huge(len))) then
      status = BW_KERNEL_BAD_FRAME
      return
    end if
    n = normal / len
    b = [0.0_c_double, 0.0_c_double, 1.0_c_double] - n(3) * n
    if (norm2(b) < 1e-6_c_double) b = [0.0_c_double, 1.0_c_double, 0.0_c_double] - n(2) * n
    b = b / norm2(b)
    t = [n(2) * b(3) - n(3) * b(2), n(3) * b(1) - n(1) * b(3), n(1) * b(2) - n(2) * b(1)]
    frame(:, 1) = t
    frame(:, 2) = n
    frame(:, 3) = b
    status = BW_KERNEL_OK
  end subroutine bw_kernel_frame

  !> The m x mb portions of a rectangle lt x lb centred on G, aligned with
  !! (t, b): equal cells, t index fastest (C: double area[m mb], xi[m mb],
  !! eta[m mb]). In 2D a joint is the rectangle l x s with mb = 1.
  pure subroutine bw_kernel_rectangle_portions(m, mb, lt, lb, area, xi, eta, status) &
       bind(C, name="bw_kernel_rectangle_portions")
    integer(c_int), value, intent(in) :: m, mb
    real(c_double), value, intent(in) :: lt, lb
    real(c_double), intent(out) :: area(m * mb), xi(m * mb), eta(m * mb)
    integer(c_int), intent(out) :: status
    real(c_double) :: rm, rmb, ap, e
    integer :: i, j
    status = BW_KERNEL_OK
    if (m < 1 .or. mb < 1) then
      status = BW_KERNEL_BAD_M
      return
    else if (.not. (lt > 0 .and. lt < huge(lt))) then
      status = BW_KERNEL_BAD_LENGTH
      return
    else if (.not. (lb > 0 .and. lb < huge(lb))) then
      status = BW_KERNEL_BAD_DEPTH
      return
    end if
    ! reciprocals once: this runs for every interface at every use
    rm = 1.0_c_double / real(m, c_double)
    rmb = 1.0_c_double / real(mb, c_double)
    ap = lt * lb * rm * rmb
    do j = 1, mb
      e = lb * ((real(j, c_double) - 0.5_c_double) * rmb - 0.5_c_double)
      do i = 1, m
        area(i + m * (j - 1)) = ap
        xi(i + m * (j - 1)) = lt * ((real(i, c_double) - 0.5_c_double) * rm - 0.5_c_double)
        eta(i + m * (j - 1)) = e
      end do
    end do
    if (mb == 1) eta = 0
  end subroutine bw_kernel_rectangle_portions

  !> R B (C: double rb[nr][2 nd]): dG per unit dof of blocks i and j, from
  !! the centroids ci, cj, the centre gc (dim coordinates each) and the frame
  !! (double frame[3][3], rows t, n, b).
  pure subroutine bw_kernel_compatibility(dim, ci, cj, gc, frame, rb, status) bind(C, name="bw_kernel_compatibility")
    integer(c_int), value, intent(in) :: dim
    real(c_double), intent(in) :: ci(dim), cj(dim), gc(dim), frame(3, 3)
    real(c_double), intent(out) :: rb(2 * dofs(dim), dofs(dim))
    integer(c_int), intent(out) :: status
    real(c_double) :: rows(6, 6), arm(3), qr(3)
    integer :: a, c, r, nd, side
    if (dim /= 2 .and. dim /= 3) then
      status = BW_KERNEL_BAD_DIMENSION
      return
    end if
    nd = dofs(dim)
    do side = 0, 1
      ! sign * R P_b: row r of Q on the translation, and since a rotation w
      ! moves G by w x arm, arm x (row r of Q) on the rotation
      arm = 0
      if (side == 0) then
        arm(1:dim) = gc(1:dim) - ci(1:dim)
      else
        arm(1:dim) = gc(1:dim) - cj(1:dim)
      end if
      rows = 0
      do r = 1, 3
        qr = frame(:, r)
        rows(r, 1:3) = qr
        rows(r, 4:6) = [arm(2) * qr(3) - arm(3) * qr(2), arm(3) * qr(1) - arm(1) * qr(3), arm(1) * qr(2) - arm(2) * qr(1)]
        rows(3 + r, 4:6) = qr
      end do
      if (side == 0) rows = -rows
      do a = 1, nd
        do c = 1, nd
          rb(side * nd + c, a) = rows(dof_index(dim, a), dof_index(dim, c))
        end do
      end do
    end do
    status = BW_KERNEL_OK
  end subroutine bw_kernel_compatibility

  !> Jumps of the np portions, j_p = E_p dG (C: double j[np][ns]) from dG
  !! (double dg[nr]). E_p is written out: in 2D its restriction
  !! [[1, 0, 0], [0, 1, xi]] to (dt, dn, phib).
  pure subroutine bw_kernel_jumps(dim, np, xi, eta, dg, j, status) bind(C, name="bw_kernel_jumps")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), intent(in) :: xi(np), eta(np), dg(dofs(dim))
    real(c_double), intent(out) :: j(stresses(dim), np)
    integer(c_int), intent(out) :: status
    integer :: p
    status = check_jumps(dim, np)
    if (status /= BW_KERNEL_OK) return
    if (dim == 3) then
      do p = 1, np
        j(1, p) = dg(1) + eta(p) * dg(5)
        j(2, p) = dg(2) + xi(p) * dg(6) - eta(p) * dg(4)
        j(3, p) = dg(3) - xi(p) * dg(5)
      end do
    else
      do p = 1, np
        j(1, p) = dg(1)
        j(2, p) = dg(2) + xi(p) * dg(3)
      end do
    end if
    status = BW_KERNEL_OK
  end subroutine bw_kernel_jumps

  !> Resultants about G, f = H r = sum_p A_p E_p^T r_p (C: double f[nr])
  !! from the portions' stresses (double r[np][ns]): (T, N, Tb, Mt, Mn, Mb),
  !! in 2D (T, N, Mb).
  pure subroutine bw_kernel_resultants(dim, np, area, xi, eta, r, f, status) bind(C, name="bw_kernel_resultants")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), intent(in) :: area(np), xi(np), eta(np), r(stresses(dim), np)
    real(c_double), intent(out) :: f(dofs(dim))
    integer(c_int), intent(out) :: status
    integer :: p
    status = check_portions(dim, np, area)
    if (status /= BW_KERNEL_OK) return
    f = 0
    if (dim == 3) then
      do p = 1, np
        f(1:3) = f(1:3) + area(p) * r(:, p)
        f(4) = f(4) - area(p) * eta(p) * r(2, p)
        f(5) = f(5) + area(p) * (eta(p) * r(1, p) - xi(p) * r(3, p))
        f(6) = f(6) + area(p) * xi(p) * r(2, p)
      end do
    else
      do p = 1, np
        f(1:2) = f(1:2) + area(p) * r(:, p)
        f(3) = f(3) + area(p) * xi(p) * r(2, p)
      end do
    end if
  end subroutine bw_kernel_resultants

  !> The sizes of the terms the two kernels above sum, for round-off
  !! bounds: |E_p| a (C: double j[np][ns]) from a non-negative a(nd), and
  !! sum_p A_p |E_p|^T |r_p| (C: double f[nd]) from r(ns, np). |x| of a
  !! product's inputs through them bounds the rounding of the product
  !! (solver/estimates.c).
  pure subroutine bw_kernel_jumps_abs(dim, np, xi, eta, a, j, status) bind(C, name="bw_kernel_jumps_abs")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), intent(in) :: xi(np), eta(np), a(dofs(dim))
    real(c_double), intent(out) :: j(stresses(dim), np)
    integer(c_int), intent(out) :: status
    integer :: p
    status = check_jumps(dim, np)
    if (status /= BW_KERNEL_OK) return
    if (dim == 3) then
      do p = 1, np
        j(1, p) = abs(a(1)) + abs(eta(p) * a(5))
        j(2, p) = abs(a(2)) + abs(xi(p) * a(6)) + abs(eta(p) * a(4))
        j(3, p) = abs(a(3)) + abs(xi(p) * a(5))
      end do
    else
      do p = 1, np
        j(1, p) = abs(a(1))
        j(2, p) = abs(a(2)) + abs(xi(p) * a(3))
      end do
    end if
    status = BW_KERNEL_OK
  end subroutine bw_kernel_jumps_abs

  pure subroutine bw_kernel_resultants_abs(dim, np, area, xi, eta, r, f, status) bind(C, name="bw_kernel_resultants_abs")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), intent(in) :: area(np), xi(np), eta(np), r(stresses(dim), np)
    real(c_double), intent(out) :: f(dofs(dim))
    integer(c_int), intent(out) :: status
    integer :: p
    status = check_portions(dim, np, area)
    if (status /= BW_KERNEL_OK) return
    f = 0
    if (dim == 3) then
      do p = 1, np
        f(1:3) = f(1:3) + area(p) * abs(r(:, p))
        f(4) = f(4) + area(p) * abs(eta(p) * r(2, p))
        f(5) = f(5) + area(p) * (abs(eta(p) * r(1, p)) + abs(xi(p) * r(3, p)))
        f(6) = f(6) + area(p) * abs(xi(p) * r(2, p))
      end do
    else
      do p = 1, np
        f(1:2) = f(1:2) + area(p) * abs(r(:, p))
        f(3) = f(3) + area(p) * abs(xi(p) * r(2, p))
      end do
    end if
  end subroutine bw_kernel_resultants_abs

  !> The two kernels above in double-double arithmetic (a value is hi + lo,
  !! |lo| <= ulp(hi) / 2: about 32 digits), for a residual computed to far
  !! below double's round-off (solver/estimates.c): j = E_p dg from dg
  !! (dg_hi, dg_lo), and f = sum_p A_p E_p^T r_p from r (r_hi, r_lo), with
  !! Knuth's two-sum and Dekker's two-product, exact in IEEE double without
  !! a fused multiply-add.
  pure subroutine bw_kernel_jumps_dd(dim, np, xi, eta, dg_hi, dg_lo, j_hi, j_lo, status) bind(C, name="bw_kernel_jumps_dd")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), intent(in) :: xi(np), eta(np), dg_hi(dofs(dim)), dg_lo(dofs(dim))
    real(c_double), intent(out) :: j_hi(stresses(dim), np), j_lo(stresses(dim), np)
    integer(c_int), intent(out) :: status
    integer :: p
    status = check_jumps(dim, np)
    if (status /= BW_KERNEL_OK) return
    ! E_p written out, as in bw_kernel_jumps
    do p = 1, np
      j_hi(:, p) = dg_hi(1:stresses(dim))
      j_lo(:, p) = dg_lo(1:stresses(dim))
      if (dim == 3) then
        call dd_add_prod(j_hi(1, p), j_lo(1, p), eta(p), dg_hi(5), dg_lo(5))
        call dd_add_prod(j_hi(2, p), j_lo(2, p), xi(p), dg_hi(6), dg_lo(6))
        call dd_add_prod(j_hi(2, p), j_lo(2, p), -eta(p), dg_hi(4), dg_lo(4))
        call dd_add_prod(j_hi(3, p), j_lo(3, p), -xi(p), dg_hi(5), dg_lo(5))
      else
        call dd_add_prod(j_hi(2, p), j_lo(2, p), xi(p), dg_hi(3), dg_lo(3))
      end if
    end do
  end subroutine bw_kernel_jumps_dd

  pure subroutine bw_kernel_resultants_dd(dim, np, area, xi, eta, r_hi, r_lo, f_hi, f_lo, status) &
       bind(C, name="bw_kernel_resultants_dd")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), intent(in) :: area(np), xi(np), eta(np), r_hi(stresses(dim), np), r_lo(stresses(dim), np)
    real(c_double), intent(out) :: f_hi(dofs(dim)), f_lo(dofs(dim))
    integer(c_int), intent(out) :: status
    real(c_double) :: th(3), tl(3)
    integer :: p, a
    status = check_portions(dim, np, area)
    if (status /= BW_KERNEL_OK) return
    f_hi = 0
    f_lo = 0
    ! E_p^T written out, as in bw_kernel_resultants: t = A_p r_p first
    do p = 1, np
      do a = 1, stresses(dim)
        th(a) = 0
        tl(a) = 0
        call dd_add_prod(th(a), tl(a), area(p), r_hi(a, p), r_lo(a, p))
        call dd_add(f_hi(a), f_lo(a), th(a), tl(a))
      end do
      if (dim == 3) then
        call dd_add_prod(f_hi(4), f_lo(4), -eta(p), th(2), tl(2))
        call dd_add_prod(f_hi(5), f_lo(5), eta(p), th(1), tl(1))
        call dd_add_prod(f_hi(5), f_lo(5), -xi(p), th(3), tl(3))
        call dd_add_prod(f_hi(6), f_lo(6), xi(p), th(2), tl(2))
      else
        call dd_add_prod(f_hi(3), f_lo(3), xi(p), th(2), tl(2))
      end if
    end do
  end subroutine bw_kernel_resultants_dd

  ! (h, l) += (y_hi + y_lo) in double-double
  pure subroutine dd_add(h, l, y_hi, y_lo)
    real(c_double), intent(inout) :: h, l
    real(c_double), intent(in) :: y_hi, y_lo
    real(c_double) :: s, t
    call two_sum(h, y_hi, s, t)
    t = t + (l + y_lo)
    call two_sum(s, t, h, l)
  end subroutine dd_add

  ! (h, l) += x (y_hi + y_lo) in double-double
  pure subroutine dd_add_prod(h, l, x, y_hi, y_lo)
    real(c_double), intent(inout) :: h, l
    real(c_double), intent(in) :: x, y_hi, y_lo
    real(c_double) :: p, e, s, t
    call two_prod(x, y_hi, p, e)
    e = e + x * y_lo
    call two_sum(h, p, s, t)
    t = t + (l + e)
    call two_sum(s, t, h, l)
  end subroutine dd_add_prod

  pure subroutine two_sum(a, b, s, e)
    real(c_double), intent(in) :: a, b
    real(c_double), intent(out) :: s, e
    real(c_double) :: bb
    s = a + b
    bb = s - a
    e = (a - (s - bb)) + (b - bb)
  end subroutine two_sum

  pure subroutine two_prod(a, b, p, e)
    real(c_double), intent(in) :: a, b
    real(c_double), intent(out) :: p, e
    real(c_double), parameter :: split = 134217729.0_c_double ! 2^27 + 1
    real(c_double) :: c, ah, al, bh, bl
    p = a * b
    c = split * a
    ah = c - (c - a)
    al = a - ah
    c = split * b
    bh = c - (c - b)
    bl = b - bh
    e = ((ah * bh - p) + ah * bl + al * bh) + al * bl
  end subroutine two_prod

  !> K_G = sum_p A_p E_p^T C_p E_p (C: double kg[nr][nr]) from the
  !! portions' ns x ns tangents, row-major (double tangent[nt][ns][ns]): nt =
  !! np, one per portion, or nt = 1, one shared by all.
  pure subroutine bw_kernel_condense(dim, np, area, xi, eta, nt, tangent, kg, status) bind(C, name="bw_kernel_condense")
    integer(c_int), value, intent(in) :: dim, np, nt
    real(c_double), intent(in) :: area(np), xi(np), eta(np), tangent(stresses(dim), stresses(dim), nt)
    real(c_double), intent(out) :: kg(dofs(dim), dofs(dim))
    integer(c_int), intent(out) :: status
    real(c_double) :: full(6, 6), c(3, 3), e(3, 6), m0, m1, m2
    integer :: p, t
    status = check_portions(dim, np, area)
    if (status /= BW_KERNEL_OK) return
    if (nt /= 1 .and. nt /= np) then
      status = BW_KERNEL_BAD_M
      return
    end if
    if (dim == 2 .and. nt == 1) then
      ! one tangent: K_G from the moments sum A_p, sum A_p xi_p, sum A_p xi_p^2
      m0 = 0
      m1 = 0
      m2 = 0
      do p = 1, np
        m0 = m0 + area(p)
        m1 = m1 + area(p) * xi(p)
        m2 = m2 + area(p) * xi(p) * xi(p)
      end do
      c(1:2, 1:2) = transpose(tangent(:, :, 1))
      kg(1:2, 1:2) = m0 * transpose(c(1:2, 1:2))
      kg(3, 1:2) = m1 * c(1:2, 2)
      kg(1:2, 3) = m1 * c(2, 1:2)
      kg(3, 3) = m2 * c(2, 2)
      return
    end if
    if (dim == 2) then
      ! E_p = [[1, 0, 0], [0, 1, xi]]: E^T C E written out
      kg = 0
      do p = 1, np
        t = merge(1, p, nt == 1)
        c(1:2, 1:2) = area(p) * transpose(tangent(:, :, t))
        kg(1:2, 1:2) = kg(1:2, 1:2) + transpose(c(1:2, 1:2))
        kg(3, 1:2) = kg(3, 1:2) + xi(p) * c(1:2, 2)
        kg(1:2, 3) = kg(1:2, 3) + xi(p) * c(2, 1:2)
        kg(3, 3) = kg(3, 3) + xi(p) * xi(p) * c(2, 2)
      end do
      return
    end if
    if (nt == 1) then
      ! one tangent: E_p = E0 + xi_p E1 + eta_p E2 is linear in the portion's
      ! centroid, so K_G is six moments of the portions times fixed products:
      ! sum A_p E_p^T C E_p = M0 E0'C E0 + Mx (E0'C E1 + E1'C E0) + Me (E0'C E2
      ! + E2'C E0) + Mxx E1'C E1 + Mee E2'C E2 + Mxe (E1'C E2 + E2'C E1)
      ! (the elastic K_G of every interface at set-up: 0.8 s of a 1e5-block
      ! 3D wall's 2 s assembly with a product per portion)
      block
        real(c_double) :: mom(6), e0(3, 6), e1(3, 6), e2(3, 6), ce0(3, 6), ce1(3, 6), ce2(3, 6)
        mom = 0
        do p = 1, np
          mom(1) = mom(1) + area(p)
          mom(2) = mom(2) + area(p) * xi(p)
          mom(3) = mom(3) + area(p) * eta(p)
          mom(4) = mom(4) + area(p) * xi(p) * xi(p)
          mom(5) = mom(5) + area(p) * eta(p) * eta(p)
          mom(6) = mom(6) + area(p) * xi(p) * eta(p)
        end do
        c = transpose(tangent(:, :, 1)) ! row-major: tangent(b, a) = C[a][b]
        e0 = portion_map(0.0_c_double, 0.0_c_double)
        e1 = portion_map(1.0_c_double, 0.0_c_double) - e0
        e2 = portion_map(0.0_c_double, 1.0_c_double) - e0
        ce0 = matmul(c, e0)
        ce1 = matmul(c, e1)
        ce2 = matmul(c, e2)
        full = mom(1) * matmul(transpose(e0), ce0) &
             + mom(2) * (matmul(transpose(e0), ce1) + matmul(transpose(e1), ce0)) &
             + mom(3) * (matmul(transpose(e0), ce2) + matmul(transpose(e2), ce0)) &
             + mom(4) * matmul(transpose(e1), ce1) + mom(5) * matmul(transpose(e2), ce2) &
             + mom(6) * (matmul(transpose(e1), ce2) + matmul(transpose(e2), ce1))
      end block
      kg = transpose(full)
      return
    end if
    full = 0
    do p = 1, np
      c = transpose(tangent(:, :, p)) ! row-major: tangent(b, a) = C[a][b]
      e = portion_map(xi(p), eta(p))
      full = full + area(p) * matmul(transpose(e), matmul(c, e))
    end do
    kg = transpose(full)
  end subroutine bw_kernel_condense

  !> The pair's stiffness (R B)^T K_G (R B) (C: double k[2 nd][2 nd]) from R B
  !! (double rb[nr][2 nd]) and K_G (double kg[nr][nr]); not symmetric when
  !! K_G is not.
  pure subroutine bw_kernel_stiffness(dim, rb, kg, k, status) bind(C, name="bw_kernel_stiffness")
    integer(c_int), value, intent(in) :: dim
    real(c_double), intent(in) :: rb(2 * dofs(dim), dofs(dim)), kg(dofs(dim), dofs(dim))
    real(c_double), intent(out) :: k(2 * dofs(dim), 2 * dofs(dim))
    integer(c_int), intent(out) :: status
    ! row-major in C: rb(c, r) = (R B)[r][c], so rb is (R B)^T; kg(b, a) =
    ! K_G[a][b], so transpose(kg) is K_G; k(b, a) = S[a][b]. The shapes are
    ! fixed per dimension so that the products are unrolled, not calls.
    if (dim == 2) then
      k = pair2(rb, kg)
    else if (dim == 3) then
      k = pair3(rb, kg)
    else
      status = BW_KERNEL_BAD_DIMENSION
      return
    end if
    status = BW_KERNEL_OK
  contains
    pure function pair2(rbt, kgt) result(kk)
      real(c_double), intent(in) :: rbt(6, 3), kgt(3, 3)
      real(c_double) :: kk(6, 6)
      kk = transpose(matmul(rbt, matmul(transpose(kgt), transpose(rbt))))
    end function pair2
    pure function pair3(rbt, kgt) result(kk)
      real(c_double), intent(in) :: rbt(12, 6), kgt(6, 6)
      real(c_double) :: kk(12, 12)
      kk = transpose(matmul(rbt, matmul(transpose(kgt), transpose(rbt))))
    end function pair3
  end subroutine bw_kernel_stiffness

  !> The ns np rows of D^ for the interface, before the dofs' own scaling:
  !! the rows of portion p are sqrt(A_p) C^1/2 E_p R B with C = diag(kt, kn,
  !! kt) the scaling stiffness (C: double d[np][ns][2 nd]); E_p written out
  !! as in bw_kernel_jumps.
  pure subroutine bw_kernel_operator(dim, np, area, xi, eta, kt, kn, rb, d, status) bind(C, name="bw_kernel_operator")
    integer(c_int), value, intent(in) :: dim, np
    real(c_double), value, intent(in) :: kt, kn
    real(c_double), intent(in) :: area(np), xi(np), eta(np), rb(2 * dofs(dim), dofs(dim))
    real(c_double), intent(out) :: d(2 * dofs(dim), stresses(dim), np)
    integer(c_int), intent(out) :: status
    real(c_double) :: at, an
    integer :: p
    status = check_portions(dim, np, area)
    if (status /= BW_KERNEL_OK) return
    if (.not. (kn > 0 .and. kn < huge(kn) .and. kt > 0 .and. kt < huge(kt))) then
      status = BW_KERNEL_BAD_STIFFNESS
      return
    end if
    do p = 1, np
      at = sqrt(area(p) * kt)
      an = sqrt(area(p) * kn)
      if (dim == 3) then
        d(:, 1, p) = at * (rb(:, 1) + eta(p) * rb(:, 5))
        d(:, 2, p) = an * (rb(:, 2) + xi(p) * rb(:, 6) - eta(p) * rb(:, 4))
        d(:, 3, p) = at * (rb(:, 3) - xi(p) * rb(:, 5))
      else
        d(:, 1, p) = at * rb(:, 1)
        d(:, 2, p) = an * (rb(:, 2) + xi(p) * rb(:, 3))
      end if
    end do
  end subroutine bw_kernel_operator

  ! ------------------------------------------ the 2D interface, as before
  ! An interface of angle theta, length l, depth s and m portions: the frame
  ! of theta and the rectangle l x s in one row of m portions.

  pure function frame2(theta) result(frame)
    real(c_double), intent(in) :: theta
    real(c_double) :: frame(3, 3)
    frame = 0
    frame(:, 1) = [cos(theta), sin(theta), 0.0_c_double]
    frame(:, 2) = [-sin(theta), cos(theta), 0.0_c_double]
    frame(:, 3) = [0.0_c_double, 0.0_c_double, 1.0_c_double]
  end function frame2

  pure function check2(length, depth, m) result(status)
    real(c_double), intent(in) :: length, depth
    integer(c_int), intent(in) :: m
    integer(c_int) :: status
    status = BW_KERNEL_OK
    if (m < 1) then
      status = BW_KERNEL_BAD_M
    else if (.not. (length > 0 .and. length < huge(length))) then
      status = BW_KERNEL_BAD_LENGTH
    else if (.not. (depth > 0 .and. depth < huge(depth))) then
      status = BW_KERNEL_BAD_DEPTH
    end if
  end function check2

  pure subroutine bw_interface_compatibility(ci, cj, gc, theta, rb, status) bind(C, name="bw_interface_compatibility")
    real(c_double), intent(in) :: ci(2), cj(2), gc(2)
    real(c_double), value, intent(in) :: theta
    real(c_double), intent(out) :: rb(6, 3)
    integer(c_int), intent(out) :: status
    call bw_kernel_compatibility(2_c_int, ci, cj, gc, frame2(theta), rb, status)
  end subroutine bw_interface_compatibility

  pure subroutine bw_interface_jumps(m, length, dg, j, status) bind(C, name="bw_interface_jumps")
    integer(c_int), value, intent(in) :: m
    real(c_double), value, intent(in) :: length
    real(c_double), intent(in) :: dg(3)
    real(c_double), intent(out) :: j(2, m)
    integer(c_int), intent(out) :: status
    real(c_double) :: area(m), xi(m), eta(m)
    status = check2(length, 1.0_c_double, m)
    if (status /= BW_KERNEL_OK) return
    call bw_kernel_rectangle_portions(m, 1_c_int, length, 1.0_c_double, area, xi, eta, status)
    call bw_kernel_jumps(2_c_int, m, xi, eta, dg, j, status)
  end subroutine bw_interface_jumps

  pure subroutine bw_interface_resultants(m, length, depth, r, f, status) bind(C, name="bw_interface_resultants")
    integer(c_int), value, intent(in) :: m
    real(c_double), value, intent(in) :: length, depth
    real(c_double), intent(in) :: r(2, m)
    real(c_double), intent(out) :: f(3)
    integer(c_int), intent(out) :: status
    real(c_double) :: area(m), xi(m), eta(m)
    status = check2(length, depth, m)
    if (status /= BW_KERNEL_OK) return
    call bw_kernel_rectangle_portions(m, 1_c_int, length, depth, area, xi, eta, status)
    call bw_kernel_resultants(2_c_int, m, area, xi, eta, r, f, status)
  end subroutine bw_interface_resultants

  pure subroutine bw_interface_condense(m, length, depth, nt, tangent, kg, status) bind(C, name="bw_interface_condense")
    integer(c_int), value, intent(in) :: m, nt
    real(c_double), value, intent(in) :: length, depth
    real(c_double), intent(in) :: tangent(4, nt)
    real(c_double), intent(out) :: kg(3, 3)
    integer(c_int), intent(out) :: status
    real(c_double) :: area(m), xi(m), eta(m)
    status = check2(length, depth, m)
    if (status /= BW_KERNEL_OK) return
    if (nt /= 1 .and. nt /= m) then
      status = BW_KERNEL_BAD_M
      return
    end if
    call bw_kernel_rectangle_portions(m, 1_c_int, length, depth, area, xi, eta, status)
    call bw_kernel_condense(2_c_int, m, area, xi, eta, nt, tangent, kg, status)
  end subroutine bw_interface_condense

  pure subroutine bw_interface_stiffness(rb, kg, k, status) bind(C, name="bw_interface_stiffness")
    real(c_double), intent(in) :: rb(6, 3), kg(3, 3)
    real(c_double), intent(out) :: k(6, 6)
    integer(c_int), intent(out) :: status
    call bw_kernel_stiffness(2_c_int, rb, kg, k, status)
  end subroutine bw_interface_stiffness

  pure subroutine bw_interface_operator(m, length, depth, kt, kn, rb, d, status) bind(C, name="bw_interface_operator")
    integer(c_int), value, intent(in) :: m
    real(c_double), value, intent(in) :: length, depth, kt, kn
    real(c_double), intent(in) :: rb(6, 3)
    real(c_double), intent(out) :: d(6, 2 * m)
    integer(c_int), intent(out) :: status
    real(c_double) :: area(m), xi(m), eta(m)
    status = check2(length, depth, m)
    if (status /= BW_KERNEL_OK) return
    call bw_kernel_rectangle_portions(m, 1_c_int, length, depth, area, xi, eta, status)
    call bw_kernel_operator(2_c_int, m, area, xi, eta, kt, kn, rb, d, status)
  end subroutine bw_interface_operator

end module bw_interface_kernels
