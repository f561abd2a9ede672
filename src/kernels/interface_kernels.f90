! Per-interface kernels of the mixed rigid-block model (model.md, paper eq. 14-28).
!
! One interface joins block i (first) to block j (second) along a flat
! segment of length l, centre G, tangent t = (cos th, sin th) and normal
! n = (-sin th, cos th) pointing from i into j. It is cut into m equal
! portions with midpoints x_p = -l/2 + (p - 1/2) l/m and areas A_p = s l/m.
!
!   dG = (dt, dn, phi) = R B q,   B = [-P_i, P_j],  q = (u1,u2,w)_i, (u1,u2,w)_j
!   P_b = [[1,0,-(G2-cb2)],[0,1,(G1-cb1)],[0,0,1]],  R = [[t1,t2,0],[n1,n2,0],[0,0,1]]
!   H r = (T, N, M):   T = sum A_p rt_p,  N = sum A_p rn_p,  M = sum A_p x_p rn_p
!   compatibility      H^T dG - G r = 0,  G = diag(A_p/kt ..., A_p/kn ...)
!   local operator     D_k = H^T R B   (2m x 6, rows rt_1..rt_m, rn_1..rn_m)
!   condensed          S_k = D_k^T G^-1 D_k = (R B)^T diag(kt A, kn A, kn I (1-1/m^2)) (R B)
!
! Every procedure is a pure subroutine, data in and data out, whose last
! argument is the status (a pure function may not write its arguments); none
! stops or prints: the caller (C, through include/blockwall/kernels.h) owns
! error reporting. Arrays are passed so that C sees them row-major: the
! Fortran array d(6, 2m) is the C array double d[2m][6].
! Lever arms G - c are formed here from the coordinates given; callers that
! work far from the origin pass coordinates relative to a nearby point.
module bw_interface_kernels
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  implicit none
  private
  public :: bw_interface_operator, bw_interface_stiffness, bw_interface_recover, &
            bw_interface_stress, bw_interface_compatibility, bw_interface_compliance

  integer(c_int), parameter, public :: BW_KERNEL_OK = 0, BW_KERNEL_BAD_M = 1, &
       BW_KERNEL_BAD_LENGTH = 2, BW_KERNEL_BAD_DEPTH = 3, BW_KERNEL_BAD_STIFFNESS = 4

contains

  pure function check_arguments(length, depth, kn, kt, m) result(status)
    real(c_double), intent(in) :: length, depth, kn, kt
    integer(c_int), intent(in) :: m
    integer(c_int) :: status
    ! The comparisons are written so that NaN fails them.
    status = BW_KERNEL_OK
    if (m < 1) then
      status = BW_KERNEL_BAD_M
    else if (.not. (length > 0 .and. length < huge(length))) then
      status = BW_KERNEL_BAD_LENGTH
    else if (.not. (depth > 0 .and. depth < huge(depth))) then
      status = BW_KERNEL_BAD_DEPTH
    else if (.not. (kn > 0 .and. kn < huge(kn) .and. kt > 0 .and. kt < huge(kt))) then
      status = BW_KERNEL_BAD_STIFFNESS
    end if
  end function check_arguments

  ! R B (3 x 6): relative displacement (dt, dn, phi) at G per unit block dof.
  pure function rotated_compatibility(ci, cj, gc, theta) result(rb)
    real(c_double), intent(in) :: ci(2), cj(2), gc(2), theta
    real(c_double) :: rb(3, 6)
    real(c_double) :: t(2), n(2), p(3, 3)
    t = [cos(theta), sin(theta)]
    n = [-sin(theta), cos(theta)]
    p = lever(ci)
    rb(:, 1:3) = -rotate(p)
    p = lever(cj)
    rb(:, 4:6) = rotate(p)
  contains
    pure function lever(c) result(pb)
      real(c_double), intent(in) :: c(2)
      real(c_double) :: pb(3, 3)
      pb = reshape([1.0_c_double, 0.0_c_double, 0.0_c_double, &
                    0.0_c_double, 1.0_c_double, 0.0_c_double, &
                    -(gc(2) - c(2)), gc(1) - c(1), 1.0_c_double], [3, 3])
    end function lever
    pure function rotate(pb) result(rp)
      real(c_double), intent(in) :: pb(3, 3)
      real(c_double) :: rp(3, 3)
      rp(1, :) = t(1) * pb(1, :) + t(2) * pb(2, :)
      rp(2, :) = n(1) * pb(1, :) + n(2) * pb(2, :)
      rp(3, :) = pb(3, :)
    end function rotate
  end function rotated_compatibility

  pure function portion_midpoint(length, m, p) result(x)
    real(c_double), intent(in) :: length
    integer(c_int), intent(in) :: m, p
    real(c_double) :: x
    x = length * ((real(p, c_double) - 0.5_c_double) / real(m, c_double) - 0.5_c_double)
  end function portion_midpoint

  !> R B (C: double rb[3][6]): relative displacement (dt, dn, phi) at G per
  !! unit dof of the two blocks; D_k = H^T (R B) without the portions.
  pure subroutine bw_interface_compatibility(ci, cj, gc, theta, rb, status) &
       bind(C, name="bw_interface_compatibility")
    real(c_double), intent(in) :: ci(2), cj(2), gc(2)
    real(c_double), value, intent(in) :: theta
    real(c_double), intent(out) :: rb(6, 3)
    integer(c_int), intent(out) :: status
    status = BW_KERNEL_OK
    rb = transpose(rotated_compatibility(ci, cj, gc, theta))
  end subroutine bw_interface_compatibility

  !> The compliance diagonal g (2m) alone: A_p/kt for the shear portions,
  !! A_p/kn for the normal ones.
  pure subroutine bw_interface_compliance(length, depth, kn, kt, m, g, status) &
       bind(C, name="bw_interface_compliance")
    real(c_double), value, intent(in) :: length, depth, kn, kt
    integer(c_int), value, intent(in) :: m
    real(c_double), intent(out) :: g(2 * m)
    integer(c_int), intent(out) :: status
    real(c_double) :: ap
    status = check_arguments(length, depth, kn, kt, m)
    if (status /= BW_KERNEL_OK) return
    ap = depth * length / real(m, c_double)
    g(1:m) = ap / kt
    g(m + 1:2 * m) = ap / kn
  end subroutine bw_interface_compliance

  !> D_k = H^T R B (C: double d[2m][6]) and the compliance diagonal g (2m).
  pure subroutine bw_interface_operator(ci, cj, gc, theta, length, depth, kn, kt, m, d, g, status) &
       bind(C, name="bw_interface_operator")
    real(c_double), intent(in) :: ci(2), cj(2), gc(2)
    real(c_double), value, intent(in) :: theta, length, depth, kn, kt
    integer(c_int), value, intent(in) :: m
    real(c_double), intent(out) :: d(6, 2 * m), g(2 * m)
    integer(c_int), intent(out) :: status
    real(c_double) :: rb(3, 6), ap
    integer(c_int) :: p
    status = check_arguments(length, depth, kn, kt, m)
    if (status /= BW_KERNEL_OK) return
    rb = rotated_compatibility(ci, cj, gc, theta)
    ap = depth * length / real(m, c_double)
    do p = 1, m
      d(:, p) = ap * rb(1, :)
      d(:, m + p) = ap * (rb(2, :) + portion_midpoint(length, m, p) * rb(3, :))
      g(p) = ap / kt
      g(m + p) = ap / kn
    end do
  end subroutine bw_interface_operator

  !> S_k = D_k^T G^-1 D_k (C: double k[6][6], symmetric), from the exact
  !! discrete interface stiffness diag(kt A, kn A, kn I (1 - 1/m^2)).
  pure subroutine bw_interface_stiffness(ci, cj, gc, theta, length, depth, kn, kt, m, k, status) &
       bind(C, name="bw_interface_stiffness")
    real(c_double), intent(in) :: ci(2), cj(2), gc(2)
    real(c_double), value, intent(in) :: theta, length, depth, kn, kt
    integer(c_int), value, intent(in) :: m
    real(c_double), intent(out) :: k(6, 6)
    integer(c_int), intent(out) :: status
    real(c_double) :: rb(3, 6), kg(3), area, inertia
    integer :: a, b
    status = check_arguments(length, depth, kn, kt, m)
    if (status /= BW_KERNEL_OK) return
    rb = rotated_compatibility(ci, cj, gc, theta)
    area = depth * length
    inertia = depth * length**3 / 12.0_c_double
    kg = [kt * area, kn * area, kn * inertia * (1.0_c_double - 1.0_c_double / real(m, c_double)**2)]
    do b = 1, 6
      do a = 1, 6
        k(a, b) = sum(rb(:, a) * kg * rb(:, b))
      end do
    end do
  end subroutine bw_interface_stiffness

  !> From block dofs qi, qj and stresses r (2m): relative displacement at G
  !! dg = (dt, dn, phi) and resultants f = H r = (T, N, M), local axes.
  pure subroutine bw_interface_recover(ci, cj, gc, theta, length, depth, m, qi, qj, r, dg, f, status) &
       bind(C, name="bw_interface_recover")
    integer(c_int), value, intent(in) :: m
    real(c_double), intent(in) :: ci(2), cj(2), gc(2), qi(3), qj(3), r(2 * m)
    real(c_double), value, intent(in) :: theta, length, depth
    real(c_double), intent(out) :: dg(3), f(3)
    integer(c_int), intent(out) :: status
    real(c_double) :: rb(3, 6), ap
    integer(c_int) :: p
    status = check_arguments(length, depth, 1.0_c_double, 1.0_c_double, m)
    if (status /= BW_KERNEL_OK) return
    rb = rotated_compatibility(ci, cj, gc, theta)
    dg = matmul(rb(:, 1:3), qi) + matmul(rb(:, 4:6), qj)
    ap = depth * length / real(m, c_double)
    f = 0
    do p = 1, m
      f(1) = f(1) + ap * r(p)
      f(2) = f(2) + ap * r(m + p)
      f(3) = f(3) + ap * portion_midpoint(length, m, p) * r(m + p)
    end do
  end subroutine bw_interface_recover

  !> Stresses r = G^-1 H^T R B q (2m) of the displacement-only (condensed)
  !! model: rt_p = kt dt, rn_p = kn (dn + x_p phi).
  pure subroutine bw_interface_stress(ci, cj, gc, theta, length, depth, kn, kt, m, qi, qj, r, status) &
       bind(C, name="bw_interface_stress")
    real(c_double), intent(in) :: ci(2), cj(2), gc(2), qi(3), qj(3)
    real(c_double), value, intent(in) :: theta, length, depth, kn, kt
    integer(c_int), value, intent(in) :: m
    real(c_double), intent(out) :: r(2 * m)
    integer(c_int), intent(out) :: status
    real(c_double) :: rb(3, 6), dg(3)
    integer(c_int) :: p
    status = check_arguments(length, depth, kn, kt, m)
    if (status /= BW_KERNEL_OK) return
    rb = rotated_compatibility(ci, cj, gc, theta)
    dg = matmul(rb(:, 1:3), qi) + matmul(rb(:, 4:6), qj)
    do p = 1, m
      r(p) = kt * dg(1)
      r(m + p) = kn * (dg(2) + portion_midpoint(length, m, p) * dg(3))
    end do
  end subroutine bw_interface_stress

end module bw_interface_kernels
