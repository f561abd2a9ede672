! Per-interface kernels of the mixed rigid-block model (model.md, paper eq. 14-28).
!
! One interface joins block i (first) to block j (second) along a flat
! segment of length l, centre G, tangent t = (cos th, sin th) and normal
! n = (-sin th, cos th) pointing from i into j. It is cut into m equal
! portions with midpoints x_p = -l/2 + (p - 1/2) l/m and areas A_p = s l/m.
! Each portion carries a jump j_p and a stress r_p, interleaved as
! (shear, normal) pairs, portion after portion:
!
!   dG  = (dt, dn, phi) = R B q,   B = [-P_i, P_j],  q = (u1,u2,w)_i, (u1,u2,w)_j
!   P_b = [[1,0,-(G2-cb2)],[0,1,(G1-cb1)],[0,0,1]],  R = [[t1,t2,0],[n1,n2,0],[0,0,1]]
!   j_p = E_p dG,   E_p = [[1,0,0],[0,1,x_p]]               (jump at the portion)
!   H r = (T, N, M) = sum_p A_p E_p^T r_p                   (resultants about G)
!   K_G = sum_p A_p E_p^T C_p E_p                           (interface stiffness, 3x3,
!         from the portions' 2x2 tangents C_p; elastic C = diag(kt, kn) gives
!         diag(kt A, kn A, kn I (1 - 1/m^2)): T and N exact, bending error 1/m^2)
!   S_k = (R B)^T K_G (R B)                                 (6x6, the pair's stiffness)
!   D^ rows of portion p, scaled by the compliance G_p^-1/2 = sqrt(A_p) C^1/2,
!   C = diag(kt, kn) the scaling stiffness:  sqrt(A_p) C^1/2 E_p R B
!
! The portion map E_p, its transpose H and x_p are defined here and nowhere
! else: the assembled and the shell forms of D^, the jumps a joint law sees
! and the resultants written all come from these procedures.
!
! Every procedure is a pure subroutine, data in and data out, whose last
! argument is the status (a pure function may not write its arguments); none
! stops or prints: the caller (C, through include/blockwall/kernels.h) owns
! error reporting. Arrays are passed so that C sees them row-major: the
! Fortran array k(6, 6) is the C array double k[6][6] with k[a][b] = k(b, a).
! Lever arms G - c are formed here from the coordinates given; callers that
! work far from the origin pass coordinates relative to a nearby point.
module bw_interface_kernels
  use, intrinsic :: iso_c_binding, only: c_double, c_int
  implicit none
  private
  public :: bw_interface_compatibility, bw_interface_jumps, bw_interface_resultants, &
            bw_interface_condense, bw_interface_stiffness, bw_interface_operator

  integer(c_int), parameter, public :: BW_KERNEL_OK = 0, BW_KERNEL_BAD_M = 1, &
       BW_KERNEL_BAD_LENGTH = 2, BW_KERNEL_BAD_DEPTH = 3, BW_KERNEL_BAD_STIFFNESS = 4

contains

  ! The comparisons are written so that NaN fails them.
  pure function check_portions(length, depth, m) result(status)
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
  end function check_portions

  pure function portion_midpoint(length, m, p) result(x)
    real(c_double), intent(in) :: length
    integer(c_int), intent(in) :: m, p
    real(c_double) :: x
    x = length * ((real(p, c_double) - 0.5_c_double) / real(m, c_double) - 0.5_c_double)
  end function portion_midpoint

  !> R B (C: double rb[3][6]): relative displacement (dt, dn, phi) at G per
  !! unit dof of the two blocks.
  pure subroutine bw_interface_compatibility(ci, cj, gc, theta, rb, status) &
       bind(C, name="bw_interface_compatibility")
    real(c_double), intent(in) :: ci(2), cj(2), gc(2)
    real(c_double), value, intent(in) :: theta
    real(c_double), intent(out) :: rb(6, 3)
    integer(c_int), intent(out) :: status
    real(c_double) :: t(2), n(2)
    status = BW_KERNEL_OK
    t = [cos(theta), sin(theta)]
    n = [-sin(theta), cos(theta)]
    call side(ci, -1.0_c_double, rb(1:3, :))
    call side(cj, 1.0_c_double, rb(4:6, :))
  contains
    ! sign * R P_b: the columns of one block
    pure subroutine side(c, sgn, cols)
      real(c_double), intent(in) :: c(2), sgn
      real(c_double), intent(out) :: cols(3, 3)
      real(c_double) :: arm(2)
      arm = [-(gc(2) - c(2)), gc(1) - c(1)]  ! P_b's third column: rotation moves G by arm
      cols(:, 1) = sgn * [t(1), t(2), t(1) * arm(1) + t(2) * arm(2)]
      cols(:, 2) = sgn * [n(1), n(2), n(1) * arm(1) + n(2) * arm(2)]
      cols(:, 3) = sgn * [0.0_c_double, 0.0_c_double, 1.0_c_double]
    end subroutine side
  end subroutine bw_interface_compatibility

  !> Jumps of the m portions, j_p = E_p dG = (dt, dn + x_p phi), as
  !! (shear, normal) pairs (C: double j[2m]).
  pure subroutine bw_interface_jumps(m, length, dg, j, status) bind(C, name="bw_interface_jumps")
    integer(c_int), value, intent(in) :: m
    real(c_double), value, intent(in) :: length
    real(c_double), intent(in) :: dg(3)
    real(c_double), intent(out) :: j(2, m)
    integer(c_int), intent(out) :: status
    integer(c_int) :: p
    status = check_portions(length, 1.0_c_double, m)
    if (status /= BW_KERNEL_OK) return
    do p = 1, m
      j(1, p) = dg(1)
      j(2, p) = dg(2) + portion_midpoint(length, m, p) * dg(3)
    end do
  end subroutine bw_interface_jumps

  !> Resultants about G, f = H r = (T, N, M) = sum_p A_p E_p^T r_p, from the
  !! portions' (shear, normal) pairs r (C: double r[2m]).
  pure subroutine bw_interface_resultants(m, length, depth, r, f, status) bind(C, name="bw_interface_resultants")
    integer(c_int), value, intent(in) :: m
    real(c_double), value, intent(in) :: length, depth
    real(c_double), intent(in) :: r(2, m)
    real(c_double), intent(out) :: f(3)
    integer(c_int), intent(out) :: status
    real(c_double) :: ap
    integer(c_int) :: p
    status = check_portions(length, depth, m)
    if (status /= BW_KERNEL_OK) return
    ap = depth * length / real(m, c_double)
    f = 0
    do p = 1, m
      f(1) = f(1) + r(1, p)
      f(2) = f(2) + r(2, p)
      f(3) = f(3) + portion_midpoint(length, m, p) * r(2, p)
    end do
    f = ap * f
  end subroutine bw_interface_resultants

  !> Interface stiffness K_G = sum_p A_p E_p^T C_p E_p (C: double kg[3][3],
  !! (t, n, phi) local) from the portions' 2x2 tangents C_p, row-major
  !! (drt/ddt, drt/ddn, drn/ddt, drn/ddn): nt = m tangents, one per portion,
  !! or nt = 1 for one tangent shared by all (an elastic law), summed in
  !! closed form (sum x_p = 0, sum A_p x_p^2 = I (1 - 1/m^2)).
  pure subroutine bw_interface_condense(m, length, depth, nt, tangent, kg, status) bind(C, name="bw_interface_condense")
    integer(c_int), value, intent(in) :: m, nt
    real(c_double), value, intent(in) :: length, depth
    real(c_double), intent(in) :: tangent(4, nt)
    real(c_double), intent(out) :: kg(3, 3)
    integer(c_int), intent(out) :: status
    real(c_double) :: ap, x, c(2, 2), s(3, 3)
    integer(c_int) :: p
    status = check_portions(length, depth, m)
    if (status /= BW_KERNEL_OK) return
    if (nt /= 1 .and. nt /= m) then
      status = BW_KERNEL_BAD_M
      return
    end if
    ap = depth * length / real(m, c_double)
    if (nt == 1) then
      c = reshape(tangent(:, 1), [2, 2], order=[2, 1])
      s = 0
      s(1:2, 1:2) = ap * real(m, c_double) * c
      s(3, 3) = c(2, 2) * depth * length**3 / 12.0_c_double * (1.0_c_double - 1.0_c_double / real(m, c_double)**2)
    else
      s = 0
      do p = 1, m
        x = portion_midpoint(length, m, p)
        c = ap * reshape(tangent(:, p), [2, 2], order=[2, 1])
        ! E_p^T c E_p with E_p = [[1,0,0],[0,1,x]]
        s(1:2, 1:2) = s(1:2, 1:2) + c
        s(1:2, 3) = s(1:2, 3) + x * c(:, 2)
        s(3, 1:2) = s(3, 1:2) + x * c(2, :)
        s(3, 3) = s(3, 3) + x * x * c(2, 2)
      end do
    end if
    kg = transpose(s)
  end subroutine bw_interface_condense

  !> The pair's stiffness S_k = (R B)^T K_G (R B) (C: double k[6][6]) from
  !! R B (double rb[3][6]) and K_G (double kg[3][3]); not symmetric when K_G
  !! is not.
  pure subroutine bw_interface_stiffness(rb, kg, k, status) bind(C, name="bw_interface_stiffness")
    real(c_double), intent(in) :: rb(6, 3), kg(3, 3)
    real(c_double), intent(out) :: k(6, 6)
    integer(c_int), intent(out) :: status
    ! row-major in C: rb(c, r) = (R B)[r][c], so rb is (R B)^T; kg(b, a) =
    ! K_G[a][b], so transpose(kg) is K_G; k(b, a) = S[a][b]
    k = transpose(matmul(rb, matmul(transpose(kg), transpose(rb))))
    status = BW_KERNEL_OK
  end subroutine bw_interface_stiffness

  !> The 2m rows of D^ for the interface, before the dofs' own scaling: row
  !! pair p is sqrt(A_p) C^1/2 E_p R B with C = diag(kt, kn) the scaling
  !! stiffness (C: double d[2m][6], rows shear 1, normal 1, shear 2, ...).
  pure subroutine bw_interface_operator(m, length, depth, kt, kn, rb, d, status) bind(C, name="bw_interface_operator")
    integer(c_int), value, intent(in) :: m
    real(c_double), value, intent(in) :: length, depth, kt, kn
    real(c_double), intent(in) :: rb(6, 3)
    real(c_double), intent(out) :: d(6, 2 * m)
    integer(c_int), intent(out) :: status
    real(c_double) :: at, an
    integer(c_int) :: p
    status = check_portions(length, depth, m)
    if (status /= BW_KERNEL_OK) return
    if (.not. (kn > 0 .and. kn < huge(kn) .and. kt > 0 .and. kt < huge(kt))) then
      status = BW_KERNEL_BAD_STIFFNESS
      return
    end if
    at = sqrt(depth * length / real(m, c_double) * kt)
    an = sqrt(depth * length / real(m, c_double) * kn)
    do p = 1, m
      d(:, 2 * p - 1) = at * rb(:, 1)
      d(:, 2 * p) = an * (rb(:, 2) + portion_midpoint(length, m, p) * rb(:, 3))
    end do
  end subroutine bw_interface_operator

end module bw_interface_kernels
