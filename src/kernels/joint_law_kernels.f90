! Per-portion joint laws of the mixed rigid-block model (model.md, "Nonlinear joints").
!
! A portion carries the jump j = (dt, dn) [m], tension and opening positive, and the
! state (slip, opening, k1, k2): the plastic jump jpl = (slip, opening) [m], the
! accumulated plastic opening k1 and plastic slip k2 [m]. Its stress [Pa] is
!   r = (rt, rn) = C (j - jpl),   C = diag(kt, kn) [N/m^3].
! Strength: three linear surfaces, the Coulomb cone |rt| + rn tanphi <= c split into
! two halves that share k2, each with a constant flow vector m_a (d jpl = sum dl_a m_a):
!   f1  =  rn             - ft(k1) <= 0   gradient (0, 1)         flow (0, 1)          dk1 = dl1
!   f2+ =  rt + rn tanphi - c(k2)  <= 0   gradient (+1, tanphi)   flow (+1, tanpsi)    dk2 = dl2+ + dl2-
!   f2- = -rt + rn tanphi - c(k2)  <= 0   gradient (-1, tanphi)   flow (-1, tanpsi)
! (the flow of g2 = |rt| + rn tanpsi, whose multiplier dl2 = dl2+ + dl2-), with
!   ft(k1) = ft0 exp(-ft0 k1 / GfI),  c(k2) = c0 exp(-c0 k2 / GfII)
! where GfI, GfII > 0 (so int ft dk1 = GfI, int c dk2 = GfII), constant otherwise.
!
! Backward Euler from the converged state (jpl_n, k_n) to the trial jump j, with the
! trial stress r_tr = C (j - jpl_n); for an active set J (Koiter's rule):
!   r = r_tr - C sum_J dl_a m_a,   f_a(r, k_n + dk) = 0 and dl_a >= 0 (a in J),
!   f_b(r, k_n + dk) <= 0 for every b.
! The set is the first admissible one (multipliers >= 0, no surface violated beyond
! 1e-12 of the trial stress) of:
!   elastic  every f_b(r_tr, k_n) <= 0: r = r_tr, tangent C, state unchanged.
!   single   a surface violated at trial: dl = f_tr / (n.C m) in closed form without
!            softening; with it, the root of a concave scalar equation, bracketed
!            between the frozen-strength return and n.r_tr / n.C m (Newton, bisection
!            when a step leaves the bracket).
!   pair     {1,2+}, {1,2-}: corners of cut-off and cone; {2+,2-}: the cone's apex
!            (rt = 0, rn = c/tanphi, reachable when it lies below the cut-off, e.g.
!            after c softened). Closed form A0 dl = f_tr without softening. With it:
!            at the apex rt = 0 fixes dl2+ - dl2-, and the sum solves a bracketed
!            scalar equation from |dl2+ - dl2-| on; at a corner without dilatancy the
!            cut-off's equation holds dl1 alone, so two bracketed scalar equations in
!            turn; at a corner with dilatancy a 2x2 Newton with backtracking started
!            from the frozen-strength return. A pair whose gradients or flows are
!            dependent is skipped: tanphi = 0 (parallel f2+-) or tanpsi = 0 (no normal
!            flow at the apex).
!            A single return whose stress also lies on another surface is used only
!            when no pair is admissible: the larger set gives the derivative of the
!            neighbourhood (e.g. an open dry joint has no shear stiffness).
!   apex with tanpsi = 0: the cone's flow has no normal part, so a trial above an apex
!            lying below the cut-off has no return in the law above. There the cut-off
!            is lowered to the apex, f1* = rn - min(ft(k1), c(k2)/tanphi):
!            rt = 0, rn = c(k2)/tanphi, dk2 = |d slip| = |rt_tr|/kt, dk1 = d opening,
!            mode 3; tangent: drn/ddt = c'(k2) sign(d slip) / tanphi, the rest zero.
! With softening moduli below the stiffnesses (ft0^2/GfI < kn, c0^2/GfII < kt) every
! random trial of tests/unit/test_laws.c finds an admissible set, some at 0.99 of that
! bound; past it (a local snap-back) the step may have several solutions or none that
! this search finds, and the status is BW_LAW_NOT_CONVERGED.
! Consistent tangent of the active set, by implicit differentiation of the equations:
!   dr/dj = C - C M A^-1 N^T C,   A_ab = n_a.C m_b + ds_a/dk [k_a is k_b],
! N, M the gradients and flows of the set, s_a its strength (ft or c), ds/dk <= 0:
! C when elastic, zero at a corner of perfectly plastic surfaces, non-symmetric when
! tanpsi /= tanphi.
!
! Pure subroutines, data in and data out, status last (BW_LAW_* in
! include/blockwall/laws.h); none stops or prints. Arrays are interleaved per portion:
! the Fortran array jump(ns, n) is the C array double jump[n][ns]. The same kernels
! serve 2D (ns = 2) and 3D (ns = 3: the return in the cone's meridian plane, below).
module bw_joint_law_kernels
  use, intrinsic :: iso_c_binding, only: c_double, c_int, c_signed_char
  implicit none
  private
  public :: bw_law_elastic, bw_law_coulomb, bw_law_coulomb_cap

  integer(c_int), parameter, public :: BW_LAW_OK = 0, BW_LAW_BAD_STIFFNESS = 1, &
       BW_LAW_BAD_STRENGTH = 2, BW_LAW_NOT_CONVERGED = 3, BW_LAW_BAD_JUMP = 4, BW_LAW_BAD_STATE = 5, &
       BW_LAW_BAD_SIZE = 6

  ! Positions in par (BW_LAW_PAR_* + 1); a portion's state is (slip, opening, k1, k2).
  integer, parameter :: NPAR = 12, NSTATE = 4
  integer, parameter :: IKT = 1, IKN = 2, IFT = 3, ICOH = 4, ITANPHI = 5, ITANPSI = 6, IGFI = 7
  ! The cap's parameters: fc, Css, Gfc, kappa_p.
  integer, parameter :: IFC = 9, ICSS = 10, IGFC = 11, IKP = 12
  ! A portion's state with ns stress components: (slip, opening, k1, k2, k3[, slip_b]);
  ! the Coulomb return works on its first NSTATE entries, the cap adds k3.
  integer, parameter :: NSTATE_2D = NSTATE + 1, IK3 = NSTATE + 1, ISLIPB = NSTATE + 2
  ! The internal variable of each surface: k1 for the cut-off, k2 for both cone halves.
  integer, parameter :: KVAR(3) = [1, 2, 2]
  ! Pairs in the order tried: the corners with the cut-off before the apex, so that a
  ! joint whose apex lies on the cut-off (no-tension dry joint) opens on the cut-off;
  ! the corner with the cone's half the trial shear points to first (coulomb_portion).
  integer, parameter :: PAIRS(2, 3) = reshape([1, 2, 1, 3, 2, 3], [2, 3])

  real(c_double), parameter :: ZERO = 0.0_c_double, ONE = 1.0_c_double, HALF = 0.5_c_double
  ! Local solves' residual and the elastic test, relative to the portion's stress scale
  ! (round-off is ~1e-16).
  real(c_double), parameter :: RTOL = 1.0e-14_c_double
  ! Active-set tests (signs of multipliers, surfaces at a candidate's stress): looser
  ! than RTOL so that a converged candidate is never rejected for its own residual.
  real(c_double), parameter :: ATOL = 1.0e-12_c_double
  ! Exponent cap: only Newton iterates with k < 0 (rejected candidates) come near it.
  real(c_double), parameter :: MAXEXP = 600.0_c_double
  integer, parameter :: MAXIT = 100, MAXHALVE = 40

  type :: law_t
    real(c_double) :: kt = ZERO, kn = ZERO, tphi = ZERO, tpsi = ZERO
    real(c_double) :: s0(2) = ZERO   ! ft0, c0
    real(c_double) :: rate(2) = ZERO ! ft0/GfI, c0/GfII; zero without softening
    real(c_double) :: nv(2, 3) = ZERO, mv(2, 3) = ZERO, cm(2, 3) = ZERO ! n_a, m_a, C m_a
    ! The compressive cap (model.md, "Compressive cap"): Css, and sbar(k3) through
    ! sp = fc, si = fc/3, sm = fc/2, sr = fc/10, kp, km, mm; soft: Gfc given (else
    ! sbar = fc, perfectly plastic).
    logical :: cap = .false., soft = .false.
    real(c_double) :: css = ZERO, sp = ZERO, si = ZERO, sm = ZERO, sr = ZERO, kp = ZERO, km = ZERO, mm = ZERO
  end type law_t

  type :: candidate_t
    logical :: valid = .false., strict = .false., failed = .false.
    real(c_double) :: dl(3) = ZERO, r(2) = ZERO, k(2) = ZERO, t(2, 2) = ZERO
    real(c_double) :: s(2) = ZERO ! strength(law, k): the exponentials once per candidate
    real(c_double) :: mu = ZERO, k3 = ZERO ! the cap's multiplier and k3 (cap_return)
  end type candidate_t

contains

  pure logical function finite(x)
    real(c_double), intent(in) :: x
    finite = abs(x) <= huge(x) ! false for NaN and infinities
  end function finite

  pure function check_stiffness(par) result(status)
    real(c_double), intent(in) :: par(NPAR)
    integer(c_int) :: status
    status = BW_LAW_OK
    if (.not. (par(IKT) > 0 .and. finite(par(IKT)) .and. par(IKN) > 0 .and. finite(par(IKN)))) &
         status = BW_LAW_BAD_STIFFNESS
  end function check_stiffness

  pure function check_portion(state, jump) result(status)
    real(c_double), intent(in) :: state(NSTATE), jump(2)
    integer(c_int) :: status
    integer :: i
    status = BW_LAW_OK
    if (.not. (finite(jump(1)) .and. finite(jump(2)))) then
      status = BW_LAW_BAD_JUMP
      return
    end if
    do i = 1, NSTATE
      if (.not. finite(state(i))) status = BW_LAW_BAD_STATE
    end do
    if (.not. (state(3) >= 0 .and. state(4) >= 0)) status = BW_LAW_BAD_STATE
  end function check_portion

  pure subroutine make_law(par, with_cap, law, status)
    real(c_double), intent(in) :: par(NPAR)
    logical, intent(in) :: with_cap
    type(law_t), intent(out) :: law
    integer(c_int), intent(out) :: status
    integer :: i
    status = check_stiffness(par)
    if (status /= BW_LAW_OK) return
    do i = IFT, ITANPSI
      if (.not. (par(i) >= 0 .and. finite(par(i)))) status = BW_LAW_BAD_STRENGTH
    end do
    if (.not. (par(ITANPSI) <= par(ITANPHI))) status = BW_LAW_BAD_STRENGTH
    if (status /= BW_LAW_OK) return
    law%kt = par(IKT)
    law%kn = par(IKN)
    law%tphi = par(ITANPHI)
    law%tpsi = par(ITANPSI)
    law%s0 = par([IFT, ICOH])
    do i = 1, 2
      if (.not. finite(par(IGFI + i - 1))) status = BW_LAW_BAD_STRENGTH
      if (par(IGFI + i - 1) > 0 .and. law%s0(i) > 0) law%rate(i) = law%s0(i) / par(IGFI + i - 1)
      if (.not. finite(law%rate(i))) status = BW_LAW_BAD_STRENGTH
    end do
    if (with_cap) call make_cap(par, law, status)
    ! element by element: an array constructor with a variable is reshaped by a
    ! library call, and the law is made at every kernel call
    law%nv(:, 1) = [ZERO, ONE]
    law%nv(1, 2) = ONE
    law%nv(2, 2) = law%tphi
    law%nv(1, 3) = -ONE
    law%nv(2, 3) = law%tphi
    law%mv(:, 1) = [ZERO, ONE]
    law%mv(1, 2) = ONE
    law%mv(2, 2) = law%tpsi
    law%mv(1, 3) = -ONE
    law%mv(2, 3) = law%tpsi
    law%cm(1, :) = law%kt * law%mv(1, :)
    law%cm(2, :) = law%kn * law%mv(2, :)
  end subroutine make_law

  ! The cap's parameters: fc > 0, Css > 0, and with Gfc > 0 the peak plastic jump
  ! kappa_p > 0 (model.md, "Compressive cap"). km - kp = 75 Gfc/(67 fc) makes the area
  ! between sbar and sr past the peak Gfc.
  pure subroutine make_cap(par, law, status)
    real(c_double), intent(in) :: par(NPAR)
    type(law_t), intent(inout) :: law
    integer(c_int), intent(inout) :: status
    if (.not. (par(IFC) > 0 .and. finite(par(IFC)) .and. par(ICSS) > 0 .and. finite(par(ICSS)) &
         .and. finite(par(IGFC)) .and. finite(par(IKP)))) then
      status = BW_LAW_BAD_STRENGTH
      return
    end if
    law%cap = .true.
    law%css = par(ICSS)
    law%sp = par(IFC)
    law%si = par(IFC) / 3
    law%sm = par(IFC) / 2
    law%sr = par(IFC) / 10
    law%soft = par(IGFC) > 0
    if (.not. law%soft) return
    if (.not. (par(IKP) > 0)) then
      status = BW_LAW_BAD_STRENGTH
      return
    end if
    law%kp = par(IKP)
    law%km = law%kp + 75 * par(IGFC) / (67 * par(IFC))
    law%mm = 2 * (law%sm - law%sp) / (law%km - law%kp)
  end subroutine make_cap

  ! sbar(k3) and its derivative: hardening on an ellipse from si to sp at kp, a
  ! parabola down to sm at km, an exponential to sr, their slopes matching at km.
  pure subroutine cap_strength(law, k, s, ds)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: k
    real(c_double), intent(out) :: s
    real(c_double), intent(out), optional :: ds ! left out where only sbar is needed
    real(c_double) :: q, w
    if (.not. law%soft) then
      s = law%sp
      if (present(ds)) ds = ZERO
    else if (k <= ZERO) then
      ! before the cap has flowed (most portions): the branch below at q = w = 0,
      ! without its division and square root
      s = law%si
      if (present(ds)) ds = huge(ONE)
    else if (k <= law%kp) then
      q = max(k / law%kp, ZERO)
      w = sqrt(max(2 * q - q * q, ZERO))
      s = law%si + (law%sp - law%si) * w
      ! infinite at k = 0, where no converged cap state lies (k3 > 0 once it flows)
      if (present(ds)) ds = huge(ONE)
      if (present(ds) .and. w > 0) ds = (law%sp - law%si) * (ONE - q) / (law%kp * w)
    else if (k <= law%km) then
      q = (k - law%kp) / (law%km - law%kp)
      s = law%sp + (law%sm - law%sp) * q * q
      if (present(ds)) ds = 2 * (law%sm - law%sp) * q / (law%km - law%kp)
    else
      w = exp(max(law%mm * (k - law%km) / (law%sm - law%sr), -MAXEXP))
      s = law%sr + (law%sm - law%sr) * w
      if (present(ds)) ds = law%mm * w
    end if
  end subroutine cap_strength

  ! Without softening or before any (rate k = 0) the strength is s0 itself, which the
  ! exponential would return too: skipping it is the same number, and most portions of
  ! a wall are there at every evaluation.
  pure function strength(law, k) result(s)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: k(2)
    real(c_double) :: s(2)
    s(1) = strength1(law%s0(1), law%rate(1), k(1))
    s(2) = strength1(law%s0(2), law%rate(2), k(2))
  end function strength

  ! One strength, s0 exp(-rate k).
  pure function strength1(s0, rate, k) result(s)
    real(c_double), intent(in) :: s0, rate, k
    real(c_double) :: s
    s = s0
    if (rate * k /= ZERO) s = s0 * exp(min(-rate * k, MAXEXP))
  end function strength1

  pure function dstrength(law, k) result(ds)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: k(2)
    real(c_double) :: ds(2)
    ds = -law%rate * strength(law, k)
  end function dstrength

  ! (k1, k2) after the multipliers (dl1, dl2+, dl2-)
  pure function advance(kin, dl) result(k)
    real(c_double), intent(in) :: kin(2), dl(3)
    real(c_double) :: k(2)
    k = [kin(1) + dl(1), kin(2) + dl(2) + dl(3)]
  end function advance

  pure function surfaces(law, r, k) result(f)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: r(2), k(2)
    real(c_double) :: f(3)
    f = surfaces_at(law, r, strength(law, k))
  end function surfaces

  ! The same with the strengths s = strength(law, k) already at hand.
  pure function surfaces_at(law, r, s) result(f)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: r(2), s(2)
    real(c_double) :: f(3)
    f = matmul(r, law%nv) - s(KVAR)
  end function surfaces_at

  ! Admissible: multipliers of the set >= 0 and no surface violated; strict: the
  ! surfaces outside the set are not touched either.
  pure subroutine judge(law, sig, set, cand)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: sig
    integer, intent(in) :: set(:)
    type(candidate_t), intent(inout) :: cand
    real(c_double) :: f(3)
    integer :: b
    f = surfaces_at(law, cand%r, cand%s)
    cand%valid = all(cand%dl(set) * min(law%kt, law%kn) >= -ATOL * sig) .and. all(f <= ATOL * sig)
    cand%strict = .true.
    do b = 1, 3
      if (all(set /= b) .and. .not. (f(b) < -ATOL * sig)) cand%strict = .false.
    end do
  end subroutine judge

  ! Root x >= xmin >= 0 of the concave g(x) = g0 - nca x - s0 exp(-rate (k0 + x)),
  ! nca > 0: a return on one surface whose strength softens (rate > 0), xmin the least
  ! admissible multiplier. The frozen-strength return x0 = (g0 - s(k0)) / nca is the root
  ! without softening. From lo = max(x0, xmin), where g >= 0 (for lo = x0 >= 0 because
  ! the strength only decreases), to hi = max(g0 / nca, lo), where g = -s <= 0, the
  ! root is bracketed and unique: Newton steps, bisecting when one leaves the bracket
  ! (so that a local snap-back, g' > 0, cannot lose it). When g(lo) < 0 the surface is
  ! not loaded on the admissible side and x0 is returned, for the active-set test to
  ! reject. sk0 is the strength at k0 (strength1(s0, rate, k0), which the callers have),
  ! sx the strength at k0 + x on return, the same numbers as strength1 there: the
  ! exponentials are the law's cost, and each is computed once.
  pure subroutine scalar_root(g0, nca, s0, rate, k0, sk0, xmin, sig, x, sx, ok)
    real(c_double), intent(in) :: g0, nca, s0, rate, k0, sk0, xmin, sig
    real(c_double), intent(out) :: x, sx
    logical, intent(out) :: ok
    real(c_double) :: x0, lo, hi, g, dg, xn
    integer :: it
    ok = .true.
    x0 = (g0 - sk0) / nca
    x = x0
    sx = s0 ! without softening
    if (.not. (rate > 0)) return
    lo = max(x0, xmin)
    sx = strength1(s0, rate, k0 + lo)
    if (g0 - nca * lo - sx < 0) then
      if (lo /= x0) sx = strength1(s0, rate, k0 + x0)
      return
    end if
    hi = max(g0 / nca, lo)
    x = lo
    do it = 1, MAXIT
      ! the strength at x (at lo, the first time, from the test above)
      if (it > 1) sx = strength1(s0, rate, k0 + x)
      g = g0 - nca * x - sx
      if (abs(g) <= RTOL * sig) return
      if (g > 0) then
        lo = x
      else
        hi = x
      end if
      if (hi - lo <= 4 * epsilon(x) * abs(hi)) return
      dg = -nca + rate * sx
      xn = lo
      if (dg < 0) xn = x - g / dg
      if (.not. (xn > lo .and. xn < hi)) xn = HALF * (lo + hi)
      x = xn
    end do
    ok = .false.
  end subroutine scalar_root

  pure subroutine solve2(a, b, x, ok)
    real(c_double), intent(in) :: a(2, 2), b(2)
    real(c_double), intent(out) :: x(2)
    logical, intent(out) :: ok
    real(c_double) :: det
    det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
    ok = abs(det) > 1.0e-12_c_double * (abs(a(1, 1) * a(2, 2)) + abs(a(1, 2) * a(2, 1)))
    x = ZERO
    if (ok) x = [a(2, 2) * b(1) - a(1, 2) * b(2), a(1, 1) * b(2) - a(2, 1) * b(1)] / det
  end subroutine solve2

  ! dr/dj = C - C M A^-1 N^T C for the set (one or two surfaces) at internal variables k,
  ! given by their strengths s = strength(law, k) (s' = -rate s).
  pure subroutine consistent_tangent(law, set, s, t, ok)
    type(law_t), intent(in) :: law
    integer, intent(in) :: set(:)
    real(c_double), intent(in) :: s(2)
    real(c_double), intent(out) :: t(2, 2)
    logical, intent(out) :: ok
    real(c_double) :: a(2, 2), ainv(2, 2), nc(2, 2), ds(2), det, an(2)
    integer :: i, j, m
    m = size(set)
    ds = -law%rate * s
    t(1, 1) = law%kt
    t(2, 1) = ZERO
    t(1, 2) = ZERO
    t(2, 2) = law%kn
    a = ZERO
    nc = ZERO
    do i = 1, m
      nc(i, :) = [law%kt * law%nv(1, set(i)), law%kn * law%nv(2, set(i))]
      do j = 1, m
        a(i, j) = dot_product(law%nv(:, set(i)), law%cm(:, set(j)))
        if (KVAR(set(i)) == KVAR(set(j))) a(i, j) = a(i, j) + ds(KVAR(set(i)))
      end do
    end do
    if (m == 1) then
      ok = abs(a(1, 1)) > 0
      if (ok) then
        do j = 1, 2
          do i = 1, 2
            t(i, j) = t(i, j) - law%cm(i, set(1)) * nc(1, j) / a(1, 1)
          end do
        end do
      end if
    else
      det = a(1, 1) * a(2, 2) - a(1, 2) * a(2, 1)
      ok = abs(det) > 0
      if (.not. ok) return
      ainv(1, 1) = a(2, 2) / det
      ainv(2, 1) = -a(2, 1) / det
      ainv(1, 2) = -a(1, 2) / det
      ainv(2, 2) = a(1, 1) / det
      ! t - C M A^-1 N^T C written out: matmul on law%cm(:, set) copies the section
      ! into a temporary on the heap at every call
      do j = 1, 2
        an(1) = ainv(1, 1) * nc(1, j) + ainv(1, 2) * nc(2, j)
        an(2) = ainv(2, 1) * nc(1, j) + ainv(2, 2) * nc(2, j)
        do i = 1, 2
          t(i, j) = t(i, j) - (law%cm(i, set(1)) * an(1) + law%cm(i, set(2)) * an(2))
        end do
      end do
    end if
  end subroutine consistent_tangent

  ! skin = strength(law, kin)
  pure function single_return(law, rtr, kin, skin, sig, a) result(cand)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(2), skin(2), sig
    integer, intent(in) :: a
    type(candidate_t) :: cand
    real(c_double) :: nca, g0, x, s(2), rn, sx
    integer :: i
    logical :: ok
    i = KVAR(a)
    nca = dot_product(law%nv(:, a), law%cm(:, a)) ! kn, or kt + kn tanphi tanpsi
    g0 = dot_product(law%nv(:, a), rtr)
    call scalar_root(g0, nca, law%s0(i), law%rate(i), kin(i), skin(i), ZERO, sig, x, sx, ok)
    if (.not. ok) then
      cand%failed = .true.
      return
    end if
    cand%dl(a) = x
    cand%k = advance(kin, cand%dl)
    ! strength(law, cand%k): the other variable is kin's, this one the root's
    s = skin
    s(i) = sx
    cand%s = s
    ! the stress placed on the surface itself, to round-off
    if (a == 1) then
      cand%r = [rtr(1), s(1)]
    else
      rn = rtr(2) - law%cm(2, a) * x
      cand%r = [law%mv(1, a) * (s(2) - rn * law%tphi), rn]
    end if
    call consistent_tangent(law, [a], cand%s, cand%t, ok)
    cand%failed = .not. ok
    call judge(law, sig, [a], cand)
  end function single_return

  pure function unpack_pair(set, x) result(dl)
    integer, intent(in) :: set(2)
    real(c_double), intent(in) :: x(2)
    real(c_double) :: dl(3)
    dl = ZERO
    dl(set) = x
  end function unpack_pair

  pure function pair_residual(law, rtr, kin, set, x) result(res)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(2), x(2)
    integer, intent(in) :: set(2)
    real(c_double) :: res(2)
    real(c_double) :: s(2)
    call pair_residual_at(law, rtr, kin, set, x, res, s)
  end function pair_residual

  ! The same, and the strengths at the point (for their derivative -rate s).
  pure subroutine pair_residual_at(law, rtr, kin, set, x, res, s)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(2), x(2)
    integer, intent(in) :: set(2)
    real(c_double), intent(out) :: res(2), s(2)
    real(c_double) :: dl(3), f(3)
    dl = unpack_pair(set, x)
    s = strength(law, advance(kin, dl))
    f = surfaces_at(law, rtr - matmul(law%cm, dl), s)
    res = f(set)
  end subroutine pair_residual_at

  ! dependent: the pair's gradients or flows are dependent, the set is skipped;
  ! skin = strength(law, kin)
  pure subroutine pair_return(law, rtr, kin, skin, sig, set, cand, dependent)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(2), skin(2), sig
    integer, intent(in) :: set(2)
    type(candidate_t), intent(out) :: cand
    logical, intent(out) :: dependent
    real(c_double) :: a0(2, 2), a(2, 2), x(2), step(2), trial(2), res(2), rtrial(2), ds(2), s(2), alpha, l, d, f(3), sl
    integer :: i, j, it, h
    logical :: ok, converged, have_s
    do j = 1, 2
      do i = 1, 2
        a0(i, j) = dot_product(law%nv(:, set(i)), law%cm(:, set(j)))
      end do
    end do
    ! pair_residual at zero multipliers: the trial's surfaces
    f = surfaces_at(law, rtr, skin)
    res = f(set)
    have_s = .false.
    call solve2(a0, res, x, ok)
    dependent = .not. ok
    if (dependent) return
    if (set(1) == 2 .and. law%rate(2) > 0) then
      ! apex: rt = 0 fixes d = dl2+ - dl2- = rt_tr / kt, and rn tanphi = c(k2 + l) is a
      ! scalar equation in the sum l = dl2+ + dl2-, admissible from |d| on
      d = rtr(1) / law%kt
      call scalar_root(law%tphi * rtr(2), law%kn * law%tpsi * law%tphi, law%s0(2), law%rate(2), kin(2), skin(2), abs(d), &
           sig, l, sl, ok)
      x = HALF * [l + d, l - d]
      if (.not. ok) then
        cand%failed = .true.
        return
      end if
    else if (set(1) == 1 .and. law%tpsi <= 0 .and. any(law%rate > 0)) then
      ! corner without dilatancy: the cut-off's equation does not involve dl2, so two
      ! scalar equations in turn, dl1 on the cut-off, then dl2 on the cone with rn = ft
      call scalar_root(rtr(2), law%kn, law%s0(1), law%rate(1), kin(1), skin(1), ZERO, sig, x(1), s(1), ok)
      call scalar_root(law%mv(1, set(2)) * rtr(1) + law%tphi * s(1), law%kt, law%s0(2), law%rate(2), kin(2), skin(2), &
           ZERO, sig, x(2), s(2), converged)
      ! the strengths at kin + (x(1), x(2)): strength(law, cand%k) below
      have_s = .true.
      if (.not. (ok .and. converged)) then
        cand%failed = .true.
        return
      end if
    else if (any(law%rate(KVAR(set)) > 0)) then
      converged = .false.
      do it = 1, MAXIT
        call pair_residual_at(law, rtr, kin, set, x, res, s)
        if (maxval(abs(res)) <= RTOL * sig) then
          converged = .true.
          exit
        end if
        ds = -law%rate * s
        a = a0
        do j = 1, 2
          do i = 1, 2
            if (KVAR(set(i)) == KVAR(set(j))) a(i, j) = a(i, j) + ds(KVAR(set(i)))
          end do
        end do
        call solve2(a, res, step, ok)
        if (.not. ok) exit
        alpha = ONE
        do h = 1, MAXHALVE
          trial = x + alpha * step
          rtrial = pair_residual(law, rtr, kin, set, trial)
          if (norm2(rtrial) <= (ONE - 1.0e-4_c_double * alpha) * norm2(res)) exit
          alpha = HALF * alpha
        end do
        if (h > MAXHALVE) then
          ! no decrease left: accept only a residual at the round-off floor
          converged = maxval(abs(res)) <= 100 * RTOL * sig
          exit
        end if
        x = trial
      end do
      if (.not. converged) then
        cand%failed = .true.
        return
      end if
    end if
    cand%dl = unpack_pair(set, x)
    cand%k = advance(kin, cand%dl)
    if (.not. have_s) s = strength(law, cand%k)
    cand%s = s
    ! the stress at the intersection of the two surfaces, to round-off
    if (set(1) == 1) then
      cand%r = [law%mv(1, set(2)) * (s(2) - s(1) * law%tphi), s(1)]
    else
      cand%r = [ZERO, s(2) / law%tphi]
    end if
    call consistent_tangent(law, set, cand%s, cand%t, ok)
    cand%failed = .not. ok
    call judge(law, sig, set, cand)
  end subroutine pair_return

  ! tanpsi = 0 above an apex that lies below the cut-off: the cut-off lowered to the apex.
  pure function apex_cutoff_return(law, rtr, kin, sig) result(cand)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(2), sig
    type(candidate_t) :: cand
    real(c_double) :: slip, s(2), ds(2)
    if (.not. (law%tphi > 0)) return
    slip = rtr(1) / law%kt
    cand%dl(2:3) = [max(slip, ZERO), max(-slip, ZERO)]
    s = strength(law, [kin(1), kin(2) + abs(slip)])
    cand%r = [ZERO, s(2) / law%tphi]
    cand%dl(1) = (rtr(2) - cand%r(2)) / law%kn
    cand%k = advance(kin, cand%dl)
    cand%s = strength(law, cand%k)
    ds = -law%rate * cand%s
    cand%t = ZERO
    if (abs(slip) > 0) cand%t(2, 1) = sign(ONE, slip) * ds(2) / law%tphi
    call judge(law, sig, [1, 2, 3], cand)
  end function apex_cutoff_return

  ! Outputs of an accepted candidate; the mode says which surfaces the stress lies on.
  pure subroutine accept(law, kin, sig, jump, cand, lowered_cutoff, r, t, state_new, mode)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: kin(2), sig, jump(2)
    type(candidate_t), intent(in) :: cand
    logical, intent(in) :: lowered_cutoff
    real(c_double), intent(out) :: r(2), t(2, 2), state_new(NSTATE)
    integer(c_signed_char), intent(out) :: mode
    real(c_double) :: f(3)
    integer :: m
    r = cand%r
    t = cand%t
    ! multipliers within round-off of zero count as zero: k never decreases
    state_new(3:4) = advance(kin, max(cand%dl, ZERO))
    state_new(1:2) = jump - [r(1) / law%kt, r(2) / law%kn]
    if (all(cand%dl >= ZERO)) then
      f = surfaces_at(law, r, cand%s) ! state_new(3:4) is cand%k
    else
      f = surfaces(law, r, state_new(3:4))
    end if
    m = 0
    if (f(1) >= -ATOL * sig) m = 1
    if (max(f(2), f(3)) >= -ATOL * sig) m = m + 2
    if (lowered_cutoff) m = 3
    mode = int(m, c_signed_char)
  end subroutine accept

  pure subroutine coulomb_portion(law, state, jump, r, t, state_new, mode, status)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: state(NSTATE), jump(2)
    real(c_double), intent(out) :: r(2), t(2, 2), state_new(NSTATE)
    integer(c_signed_char), intent(out) :: mode
    integer(c_int), intent(out) :: status
    type(candidate_t) :: cand, backup
    real(c_double) :: rtr(2), kin(2), s(2), sig, ftr(3)
    integer :: a, q, order(3)
    logical :: dependent, apex_dependent, have_backup

    rtr = [law%kt * (jump(1) - state(1)), law%kn * (jump(2) - state(2))]
    kin = state(3:4)
    status = BW_LAW_OK
    ! A trial inside the cone's compressive part, n_a.r_tr <= 0 for every surface, is
    ! elastic whatever the strengths s >= 0 are (f_a = n_a.r_tr - s_a <= 0 in floating
    ! point too): their exponentials are left out (a closed crack under compression).
    ftr = surfaces_at(law, rtr, [ZERO, ZERO])
    if (all(ftr <= ZERO)) then
      s = ZERO
    else
      s = strength(law, kin)
      ftr = ftr - s(KVAR) ! surfaces_at(law, rtr, s), the same numbers
    end if
    sig = max(abs(rtr(1)), abs(rtr(2)) * max(ONE, law%tphi), s(1), s(2))
    if (all(ftr <= RTOL * sig)) then
      r = rtr
      t(:, 1) = [law%kt, ZERO]
      t(:, 2) = [ZERO, law%kn]
      state_new = state
      mode = 0_c_signed_char
      return
    end if

    have_backup = .false.
    do a = 1, 3
      if (ftr(a) <= RTOL * sig) cycle
      cand = single_return(law, rtr, kin, s, sig, a)
      if (cand%failed .or. .not. cand%valid) cycle
      if (cand%strict) then
        call accept(law, kin, sig, jump, cand, .false., r, t, state_new, mode)
        return
      end if
      if (.not. have_backup) backup = cand
      have_backup = .true.
    end do
    apex_dependent = .false.
    ! A corner's multiplier on the cone's half has the sign of the trial shear beyond
    ! the corner's own (both are admissible only where they meet, within ATOL): the
    ! half rt_tr points to is tried first, which spares the other's return.
    order = merge([1, 2, 3], [2, 1, 3], rtr(1) >= 0)
    do q = 1, 3
      call pair_return(law, rtr, kin, s, sig, PAIRS(:, order(q)), cand, dependent)
      if (q == 3) apex_dependent = dependent
      if (dependent .or. cand%failed .or. .not. cand%valid) cycle
      call accept(law, kin, sig, jump, cand, .false., r, t, state_new, mode)
      return
    end do
    if (have_backup) then
      call accept(law, kin, sig, jump, backup, .false., r, t, state_new, mode)
      return
    end if
    if (apex_dependent) then
      cand = apex_cutoff_return(law, rtr, kin, sig)
      if (cand%valid) then
        call accept(law, kin, sig, jump, cand, .true., r, t, state_new, mode)
        return
      end if
    end if
    ! no admissible set: a local solve failed (or, never met, none exists)
    status = BW_LAW_NOT_CONVERGED
    r = rtr
    t = ZERO
    state_new = state
    mode = 0_c_signed_char
  end subroutine coulomb_portion

  ! ---- The compressive cap (law coulomb_cap) -------------------------------------
  ! f3 = Q - sbar(k3) <= 0, Q = sqrt(rn^2 + Css rt^2), associated flow: with the
  ! multiplier mu of model.md's form rn^2 + Css rt^2 - sbar^2, d jpl = 2 mu (Css rt, rn)
  ! and dk3 = 2 mu P, P = sqrt(Css^2 rt^2 + rn^2), the length of the plastic jump. For a
  ! given mu the return is explicit,
  !   rt = (rt_tr - kt s x) / (1 + 2 mu kt Css),  rn = (rn_tr - kn tanpsi x) / (1 + 2 mu kn),
  ! with x the multiplier of the Coulomb half s = +-1 at a corner (x = 0 on the cap
  ! alone), itself the root of the Coulomb equation at that mu (a bracketed scalar
  ! equation, as for the cone alone). What remains is one scalar equation in mu,
  ! g(mu) = Q(r(mu)) - sbar(k3 + 2 mu P) = 0, positive at mu = 0 where the cap is
  ! violated and negative once the stress has shrunk below sbar's least value: bracketed
  ! and solved by regula falsi (Illinois), robust where sbar'(k3) is infinite (the start
  ! of hardening) or negative (softening). The consistent tangent differentiates the
  ! full local system in (r, mu[, x]) implicitly (cap_tangent).

  ! The return at the cap multiplier mu with the partner surfaces `set` (0: none; 1 the
  ! cut-off, 2, 3 the cone's halves; [1, 2|3] the triple corner). At a given mu the
  ! stress is that of a law with stiffness diag(kt/at, kn/an) from the trial
  ! (rt_tr/at, rn_tr/an): the partners' return is single_return's scalar equation, or
  ! pair_return's corner, for that law.
  pure subroutine cap_point(law, rtr, kin, set, mu, sig, r, dl, k3, g, ok)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(3), mu, sig
    integer, intent(in) :: set(2)
    real(c_double), intent(out) :: r(2), dl(3), k3, g
    logical, intent(out) :: ok
    real(c_double) :: at, an, g0, nca, s, x, rs(2), sx
    type(law_t) :: scaled
    type(candidate_t) :: pair
    integer :: i, a
    logical :: dependent
    at = ONE + 2 * mu * law%kt * law%css
    an = ONE + 2 * mu * law%kn
    rs = [rtr(1) / at, rtr(2) / an]
    dl = ZERO
    ok = .true.
    r = rs
    a = set(1)
    if (set(2) > 0) then
      scaled = law
      scaled%kt = law%kt / at
      scaled%kn = law%kn / an
      scaled%cm(1, :) = scaled%kt * law%mv(1, :)
      scaled%cm(2, :) = scaled%kn * law%mv(2, :)
      call pair_return(scaled, rs, kin(1:2), strength(law, kin(1:2)), sig, set, pair, dependent)
      ok = .not. (dependent .or. pair%failed)
      if (.not. ok) return
      dl = pair%dl
      r = pair%r
    else if (a > 0) then
      g0 = law%nv(1, a) * rs(1) + law%nv(2, a) * rs(2)
      nca = law%nv(1, a) * law%cm(1, a) / at + law%nv(2, a) * law%cm(2, a) / an
      i = KVAR(a)
      call scalar_root(g0, nca, law%s0(i), law%rate(i), kin(i), strength1(law%s0(i), law%rate(i), kin(i)), ZERO, sig, &
           x, sx, ok)
      dl(a) = x
      r = [(rtr(1) - law%cm(1, a) * x) / at, (rtr(2) - law%cm(2, a) * x) / an]
    end if
    k3 = kin(3) + 2 * mu * sqrt((law%css * r(1))**2 + r(2)**2)
    call cap_strength(law, k3, s)
    g = sqrt(r(2)**2 + law%css * r(1)**2) - s
  end subroutine cap_point

  ! Gaussian elimination with partial pivoting: a x = b for the local systems (n <= 5),
  ! on the leading n x n block of fixed-size arrays (arrays of a variable size, or
  ! sections passed as such, are allocated on the heap at every call).
  pure subroutine solve_small(n, a, b, x, ok)
    integer, intent(in) :: n
    real(c_double), intent(in) :: a(5, 5), b(5, 2)
    real(c_double), intent(out) :: x(5, 2)
    logical, intent(out) :: ok
    real(c_double) :: m(5, 7), row(7), scale, f, acc
    integer :: i, j, k, p, c, w
    w = n + 2
    m(1:n, 1:n) = a(1:n, 1:n)
    m(1:n, n + 1:w) = b(1:n, :)
    scale = maxval(abs(a(1:n, 1:n)))
    ok = scale > 0 .and. scale <= huge(scale)
    x = ZERO
    if (.not. ok) return
    do j = 1, n
      p = j - 1 + maxloc(abs(m(j:n, j)), 1)
      if (.not. (abs(m(p, j)) > 1.0e-300_c_double * scale)) then
        ok = .false.
        return
      end if
      if (p /= j) then
        row(1:w) = m(j, 1:w)
        m(j, 1:w) = m(p, 1:w)
        m(p, 1:w) = row(1:w)
      end if
      do i = j + 1, n
        f = m(i, j) / m(j, j)
        do k = j, w
          m(i, k) = m(i, k) - f * m(j, k)
        end do
      end do
    end do
    do i = n, 1, -1
      do c = 1, 2
        acc = ZERO
        do k = i + 1, n
          acc = acc + m(i, k) * x(k, c)
        end do
        x(i, c) = (m(i, n + c) - acc) / m(i, i)
      end do
    end do
    ok = all(abs(x(1:n, :)) <= huge(ONE))
  end subroutine solve_small

  ! dr/dj of a return on the cap with the partners `set`: the residuals
  !   C^-1 r - (j - jpl_n) + mu grad(Q^2) + sum_b x_b m_b = 0,  Q - sbar(k3) = 0,
  !   n_b.r - s_b(k_b) = 0 (b in set),
  ! with k3 = k3_n + 2 mu P(r), differentiated in (r, mu, x_b); their derivative in j is
  ! (-I; 0), so dr/dj is the (r, r) block of the inverse Jacobian.
  pure subroutine cap_tangent(law, set, r, mu, k, k3, t, ok)
    type(law_t), intent(in) :: law
    integer, intent(in) :: set(2)
    real(c_double), intent(in) :: r(2), mu, k(2), k3
    real(c_double), intent(out) :: t(2, 2)
    logical, intent(out) :: ok
    real(c_double) :: jac(5, 5), rhs(5, 2), z(5, 2), q, p, s, ds, dk(2)
    integer :: n, i, j
    n = 3 + count(set > 0)
    jac = ZERO
    rhs = ZERO
    rhs(1, 1) = ONE
    rhs(2, 2) = ONE
    q = sqrt(r(2)**2 + law%css * r(1)**2)
    p = sqrt((law%css * r(1))**2 + r(2)**2)
    call cap_strength(law, k3, s, ds)
    jac(1, 1) = ONE / law%kt + 2 * mu * law%css
    jac(2, 2) = ONE / law%kn + 2 * mu
    jac(1:2, 3) = 2 * [law%css * r(1), r(2)]
    jac(3, 1:2) = [law%css * r(1), r(2)] / q - ds * 2 * mu * [law%css**2 * r(1), r(2)] / p
    jac(3, 3) = -ds * 2 * p
    dk = dstrength(law, k)
    do i = 1, n - 3
      jac(1:2, 3 + i) = law%mv(:, set(i))
      jac(3 + i, 1:2) = law%nv(:, set(i))
      do j = 1, n - 3
        if (KVAR(set(i)) == KVAR(set(j))) jac(3 + i, 3 + j) = -dk(KVAR(set(i)))
      end do
    end do
    call solve_small(n, jac, rhs, z, ok)
    t = z(1:2, 1:2)
  end subroutine cap_tangent

  ! The least g of cap_point on [a, b] (golden section, 60 steps: 1e-12 of the interval).
  pure subroutine cap_dip(law, rtr, kin, set, a, b, sig, m, g)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(3), a, b, sig
    integer, intent(in) :: set(2)
    real(c_double), intent(out) :: m, g
    real(c_double), parameter :: GOLD = 0.6180339887498949_c_double
    real(c_double) :: lo, hi, x1, x2, g1, g2, r(2), dl(3), k3
    integer :: it
    logical :: ok
    lo = a
    hi = b
    x1 = hi - GOLD * (hi - lo)
    x2 = lo + GOLD * (hi - lo)
    call cap_point(law, rtr, kin, set, x1, sig, r, dl, k3, g1, ok)
    call cap_point(law, rtr, kin, set, x2, sig, r, dl, k3, g2, ok)
    do it = 1, 60
      if (g1 < 0 .or. g2 < 0) exit
      if (g1 <= g2) then
        hi = x2
        x2 = x1
        g2 = g1
        x1 = hi - GOLD * (hi - lo)
        call cap_point(law, rtr, kin, set, x1, sig, r, dl, k3, g1, ok)
      else
        lo = x1
        x1 = x2
        g1 = g2
        x2 = lo + GOLD * (hi - lo)
        call cap_point(law, rtr, kin, set, x2, sig, r, dl, k3, g2, ok)
      end if
    end do
    m = x1
    g = g1
    if (g2 < g1) then
      m = x2
      g = g2
    end if
  end subroutine cap_dip

  ! Where cap_return's scan of the cap alone (points hi0 4^j, j = 0, 1, ...) may start:
  ! the index (1-based, as its loop counts) of the first point it must evaluate, the one
  ! after the last point j where g > 0 is certain, or 1. For mu' <= mu every component
  ! of r(mu') = (rt_tr / (1 + 2 mu' kt Css), rn_tr / (1 + 2 mu' kn)) is at least as
  ! large as at mu, so Q(mu') >= Q(mu), and k3(mu') = k3_n + 2 mu' P(r(mu')) lies in
  ! [k3_n, k3_n + 2 mu P(r_tr)], where sbar is at most sbar(min(k, kp)) if k3_n <= kp
  ! (it rises to sp at kp and falls after), else sbar(k3_n): so g(mu') >= Q(mu) - that,
  ! and where this bound exceeds 1e-10 of the stress scale (round-off of g is ~1e-15
  ! of it) the scan would have found g > 0 at every point up to mu. Two candidates are
  ! tried, the scan's points 4 to 16 and 64 to 256 times below mu_e = g0 / (2 max(kt Css,
  ! kn) sbar(k3_n)), where g would vanish if sbar did not change; each test costs about
  ! one evaluation of g.
  pure function cap_scan_skip(law, rtr, k3n, g0, hi0) result(first)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), k3n, g0, hi0
    integer :: first
    real(c_double) :: q0, s0, p0, mue, mu, at, an, q, kmax, smax, tol
    integer :: je, j, try
    first = 1
    q0 = sqrt(rtr(2)**2 + law%css * rtr(1)**2)
    s0 = q0 - g0 ! sbar(k3_n), as cap_point found it at mu = 0
    if (.not. (g0 > 0 .and. s0 > 0)) return
    mue = g0 / (2 * max(law%kt * law%css, law%kn) * s0)
    if (.not. (mue > 64 * hi0 .and. mue <= huge(mue))) return
    je = floor(log(mue / hi0) / log(4.0_c_double))
    p0 = sqrt((law%css * rtr(1))**2 + rtr(2)**2)
    tol = 1.0e-10_c_double * max(q0, law%sp)
    do try = 1, 2
      j = je - (2 * try - 1) ! je - 1, then je - 3
      if (j < 2) return
      mu = scale(hi0, 2 * j)
      at = ONE + 2 * mu * law%kt * law%css
      an = ONE + 2 * mu * law%kn
      q = sqrt((rtr(2) / an)**2 + law%css * (rtr(1) / at)**2)
      kmax = k3n + 2 * mu * p0
      smax = s0
      if (.not. law%soft) then
        smax = law%sp
      else if (k3n <= law%kp) then
        call cap_strength(law, min(kmax, law%kp), smax)
      end if
      if (q - smax > tol) then
        first = j + 2
        return
      end if
    end do
  end function cap_scan_skip

  ! A return on the cap with the partners `set` (cap_point).
  pure function cap_return(law, rtr, kin, sig, set) result(cand)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: rtr(2), kin(3), sig
    integer, intent(in) :: set(2)
    type(candidate_t) :: cand
    real(c_double) :: lo, hi, m, glo, ghi, g, r(2), dl(3), k3, smin, f(3), prev, gprev
    integer :: it, side, first
    logical :: ok
    cand%failed = .true.
    call cap_point(law, rtr, kin, set, ZERO, sig, r, dl, k3, glo, ok)
    if (.not. (ok .and. glo > RTOL * sig)) return
    ! The first root: sbar first hardens, then softens, so g may cross zero three times
    ! (on the cap, then off it while sbar softens faster than the stress shrinks, then on
    ! it again past the residual); the least plastic flow is the first crossing. Scanned
    ! upwards in factors of 4 from 1e-9 of the multiplier that shrinks the stress below
    ! sbar's least value, where the first sign change brackets it.
    ! At a corner g can also dip below zero and rise again between two points of the scan
    ! (past the corner the partner's multiplier turns negative and its surface holds the
    ! stress off the cap): where g rises, its least value between the last three points
    ! is sought (golden section) and, if negative, ends the bracket.
    smin = law%sp
    if (law%soft) smin = law%sr
    lo = ZERO
    prev = ZERO
    gprev = glo
    hi = 1.0e-9_c_double * max(sqrt(rtr(2)**2 + law%css * rtr(1)**2) / smin, ONE) / (2 * min(law%kt * law%css, law%kn))
    ! The cap alone: the scan's points where g is positive for sure are passed over
    ! (cap_scan_skip); from the last of them on the scan is the same, so is its bracket.
    first = 1
    if (set(1) == 0) then
      first = cap_scan_skip(law, rtr, kin(3), glo, hi)
      if (first > 1) then
        lo = scale(hi, 2 * (first - 2)) ! the point before the first one evaluated
        call cap_point(law, rtr, kin, set, lo, sig, r, dl, k3, glo, ok)
        hi = 4 * lo
      end if
    end if
    ghi = glo ! positive: past the scan's 200 points without a sign change, no return
    do it = first, 200
      call cap_point(law, rtr, kin, set, hi, sig, r, dl, k3, ghi, ok)
      if (.not. ok) return
      if (ghi < 0) exit
      if (ghi > glo .and. set(1) > 0) then
        call cap_dip(law, rtr, kin, set, prev, hi, sig, m, g)
        if (g < 0) then
          lo = prev
          glo = gprev
          hi = m
          ghi = g
          exit
        end if
      end if
      prev = lo
      gprev = glo
      lo = hi
      glo = ghi
      hi = 4 * hi
    end do
    if (.not. (ghi < 0)) return
    side = 0
    m = lo
    g = glo
    do it = 1, 4 * MAXIT
      m = (lo * ghi - hi * glo) / (ghi - glo)
      if (.not. (m > lo .and. m < hi)) m = HALF * (lo + hi)
      call cap_point(law, rtr, kin, set, m, sig, r, dl, k3, g, ok)
      if (.not. ok) return
      if (abs(g) <= RTOL * sig .or. hi - lo <= 4 * epsilon(hi) * hi) exit
      if (g < 0) then
        hi = m
        ghi = g
        if (side == -1) glo = HALF * glo
        side = -1
      else
        lo = m
        glo = g
        if (side == 1) ghi = HALF * ghi
        side = 1
      end if
    end do
    if (.not. (abs(g) <= 100 * RTOL * sig)) return
    cand%failed = .false.
    cand%r = r
    cand%mu = m
    cand%k3 = k3
    cand%dl = dl
    cand%k = advance(kin(1:2), cand%dl)
    cand%s = strength(law, cand%k)
    call cap_tangent(law, set, r, m, cand%k, k3, cand%t, ok)
    cand%failed = .not. ok
    f = surfaces_at(law, r, cand%s)
    cand%valid = all(dl * min(law%kt, law%kn) >= -ATOL * sig) .and. all(f <= ATOL * sig)
  end function cap_return

  ! The cut-off and Coulomb return (coulomb_portion), then the cap where that stress
  ! lies outside it: the cap alone, else its corner with the Coulomb half the trial
  ! shear points to, else its corner with the cut-off, else the point where all three
  ! meet (met where the cap is small against the cone: once it has softened towards
  ! fc/10, sr/sqrt(Css) is about c for masonry, and the cap cuts the cone near rn = 0).
  ! Mode bits: 1 cut-off, 2 Coulomb, 4 cap.
  pure subroutine portion_2d(law, state, jump, r, t, state_new, mode, status)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: state(NSTATE_2D), jump(2)
    real(c_double), intent(out) :: r(2), t(2, 2), state_new(NSTATE_2D)
    integer(c_signed_char), intent(out) :: mode
    integer(c_int), intent(out) :: status
    type(candidate_t) :: cand
    real(c_double) :: rtr(2), s(2), sbar, sig, f3, f(3)
    integer :: a, h, bits, order(2, 4)
    call coulomb_portion(law, state(1:NSTATE), jump, r, t, state_new(1:NSTATE), mode, status)
    state_new(IK3) = state(IK3)
    if (.not. law%cap .or. status /= BW_LAW_OK) return
    rtr = [law%kt * (jump(1) - state(1)), law%kn * (jump(2) - state(2))]
    ! Well inside the cap (most portions, most of the time): f3 = Q - sbar below the
    ! tolerance of the tests below at a bound of their scale sig (the strengths only
    ! soften, s <= s0 and sbar <= sp), so f3 < -ATOL sig and nothing below would change
    ! r, t or the mode. sbar of the committed k3 is a square root before the cap has
    ! flowed (most portions): cheaper than the Coulomb strengths' exponentials sig needs,
    ! and it lets through only what nears this portion's own cap, not every portion
    ! above the cap's least value fc/10.
    call cap_strength(law, state(IK3), sbar)
    f3 = sqrt(r(2)**2 + law%css * r(1)**2) - sbar
    if (f3 < -ATOL * max(abs(rtr(1)) * max(ONE, sqrt(law%css)), abs(rtr(2)) * max(ONE, law%tphi), &
         law%s0(1), law%s0(2), law%sp)) return
    s = strength(law, state(3:4))
    sig = max(abs(rtr(1)) * max(ONE, sqrt(law%css)), abs(rtr(2)) * max(ONE, law%tphi), s(1), s(2), sbar)
    if (f3 <= RTOL * sig) then
      ! a plastic return of the cut-off or cone that ends on the cap too (elastic trials
      ! on the cap stay mode 0, as on the other surfaces)
      if (mode /= 0 .and. f3 >= -ATOL * sig) mode = ior(mode, 4_c_signed_char)
      return
    end if
    ! the cap alone, its corner with the cone's half the trial shear points to, with the
    ! cut-off, and the three together
    h = merge(2, 3, rtr(1) >= 0)
    order(:, 1) = [0, 0]
    order(:, 2) = [h, 0]
    order(:, 3) = [1, 0]
    order(:, 4) = [1, h]
    do a = 1, 4
      cand = cap_return(law, rtr, state(3:5), sig, order(:, a))
      if (cand%failed .or. .not. cand%valid) cycle
      r = cand%r
      t = cand%t
      state_new(1:2) = jump - [r(1) / law%kt, r(2) / law%kn]
      state_new(3:4) = advance(state(3:4), max(cand%dl, ZERO))
      state_new(IK3) = cand%k3
      f = surfaces(law, r, state_new(3:4))
      bits = 4
      if (f(1) >= -ATOL * sig) bits = bits + 1
      if (max(f(2), f(3)) >= -ATOL * sig) bits = bits + 2
      mode = int(bits, c_signed_char)
      return
    end do
    status = BW_LAW_NOT_CONVERGED
    r = rtr
    t = ZERO
    state_new = state
    mode = 0_c_signed_char
  end subroutine portion_2d

  ! Three stress components (rt, rn, rb), tau = (rt, rb), shear isotropic (kt along t
  ! and b): the circular cone |tau| + rn tanphi <= c with the flow tau/|tau| (model.md,
  ! "Three dimensions"). Every surface depends on tau through |tau| only and every flow
  ! is radial in tau, while C is kt I on tau: the returned tau keeps the direction e of
  ! the trial tau, and the return is the 2D one in the meridian plane (|tau|, rn), with
  ! the trial (s, rn_tr), s = |tau_tr| >= 0. So the cone's apex and its corner with the
  ! cut-off are the 2D kernel's, not approximations. With rt' the returned |tau|:
  !   tau = rt' e,   jpl_tau += (2D plastic slip) e,
  !   d tau/d j_tau = T11 e e^T + kt (rt'/s) (I - e e^T),   d tau/d jn = T12 e,
  !   d rn/d j_tau = T21 e^T,   d rn/d jn = T22
  ! (T the 2D consistent tangent with respect to (s/kt, jn); the second term is the
  ! shrinking of the circle, de/d j_tau = kt (I - e e^T)/s). At s = 0 the direction is
  ! undefined and rt'/s is replaced by its limit T11/kt. State: (slip_t, opening, k1,
  ! k2, k3, slip_b): the 2D state with the b slip last. The cap is radial in tau too
  ! (Q = sqrt(rn^2 + Css |tau|^2), flow (Css tau, rn)), so the same reduction carries it.
  pure subroutine portion_3d(law, state, jump, r, t, state_new, mode, status)
    type(law_t), intent(in) :: law
    real(c_double), intent(in) :: state(NSTATE_2D + 1), jump(3)
    real(c_double), intent(out) :: r(3), t(3, 3), state_new(NSTATE_2D + 1)
    integer(c_signed_char), intent(out) :: mode
    integer(c_int), intent(out) :: status
    real(c_double) :: tau(2), s, e(2), state2(NSTATE_2D), state2_new(NSTATE_2D), r2(2), t2(2, 2), ratio, pe(2, 2)
    tau = law%kt * [jump(1) - state(1), jump(3) - state(ISLIPB)]
    s = norm2(tau)
    e = [ONE, ZERO]
    if (s > 0) e = tau / s
    state2 = [ZERO, state(2:NSTATE_2D)]
    call portion_2d(law, state2, [s / law%kt, jump(2)], r2, t2, state2_new, mode, status)
    if (status /= BW_LAW_OK) then
      r = [tau(1), r2(2), tau(2)]
      t = ZERO
      state_new = state
      return
    end if
    r = [r2(1) * e(1), r2(2), r2(1) * e(2)]
    ! the plastic slip of this step along e: exactly zero when nothing flows
    state_new = [state(1) + state2_new(1) * e(1), state2_new(2:NSTATE_2D), state(ISLIPB) + state2_new(1) * e(2)]
    ratio = t2(1, 1) / law%kt
    if (s > 0) ratio = r2(1) / s
    pe(:, 1) = e * e(1)
    pe(:, 2) = e * e(2)
    pe = t2(1, 1) * pe + law%kt * ratio * (reshape([ONE, ZERO, ZERO, ONE], [2, 2]) - pe)
    t(1, :) = [pe(1, 1), t2(1, 2) * e(1), pe(1, 2)]
    t(2, :) = [t2(2, 1) * e(1), t2(2, 2), t2(2, 1) * e(2)]
    t(3, :) = [pe(2, 1), t2(1, 2) * e(2), pe(2, 2)]
  end subroutine portion_3d

  ! ns stress components (2: rt, rn; 3: rt, rn, rb) and ns + 3 state entries.
  pure function check_size(ns) result(status)
    integer(c_int), intent(in) :: ns
    integer(c_int) :: status
    status = BW_LAW_OK
    if (ns /= 2 .and. ns /= 3) status = BW_LAW_BAD_SIZE
  end function check_size

  ! The jump's and the state's finiteness, k1, k2, k3 >= 0; the b slip of 3D is
  ! checked with the rest.
  pure function check_portion_ns(ns, state, jump) result(status)
    integer(c_int), intent(in) :: ns
    real(c_double), intent(in) :: state(:), jump(:)
    integer(c_int) :: status
    status = check_portion(state(1:NSTATE), jump(1:2))
    if (status /= BW_LAW_OK) return
    if (.not. (finite(state(IK3)) .and. state(IK3) >= 0)) status = BW_LAW_BAD_STATE
    if (ns == 3) then
      if (.not. finite(jump(3))) status = BW_LAW_BAD_JUMP
      if (status == BW_LAW_OK .and. .not. finite(state(ISLIPB))) status = BW_LAW_BAD_STATE
    end if
  end function check_portion_ns

  !> Linear joint: r = C (j - jpl) with jpl from state_in, tangent C, state copied.
  pure subroutine bw_law_elastic(ns, n, par, state_in, jump, stress, tangent, state_out, mode, status) &
       bind(C, name="bw_law_elastic")
    integer(c_int), value, intent(in) :: ns, n
    real(c_double), intent(in) :: par(NPAR), state_in(ns + 3, n), jump(ns, n)
    real(c_double), intent(out) :: stress(ns, n), tangent(ns * ns, n), state_out(ns + 3, n)
    integer(c_signed_char), intent(out) :: mode(n)
    integer(c_int), intent(out) :: status
    real(c_double) :: c(3), jpl(3)
    integer(c_int) :: p, a
    status = check_size(ns)
    if (status /= BW_LAW_OK) return
    status = check_stiffness(par)
    if (status /= BW_LAW_OK) return
    c = [par(IKT), par(IKN), par(IKT)]
    do p = 1, n
      status = check_portion_ns(ns, state_in(:, p), jump(:, p))
      if (status /= BW_LAW_OK) return
      jpl(1:2) = state_in(1:2, p)
      if (ns == 3) jpl(3) = state_in(ISLIPB, p)
      stress(:, p) = c(1:ns) * (jump(:, p) - jpl(1:ns))
      tangent(:, p) = ZERO
      do a = 1, ns
        tangent((a - 1) * ns + a, p) = c(a)
      end do
      state_out(:, p) = state_in(:, p)
      mode(p) = 0_c_signed_char
    end do
  end subroutine bw_law_elastic

  ! The nonlinear laws, with or without the cap.
  pure subroutine plastic_kernel(with_cap, ns, n, par, state_in, jump, stress, tangent, state_out, mode, status)
    logical, intent(in) :: with_cap
    integer(c_int), intent(in) :: ns, n
    real(c_double), intent(in) :: par(NPAR), state_in(ns + 3, n), jump(ns, n)
    real(c_double), intent(out) :: stress(ns, n), tangent(ns * ns, n), state_out(ns + 3, n)
    integer(c_signed_char), intent(out) :: mode(n)
    integer(c_int), intent(out) :: status
    type(law_t) :: law
    real(c_double) :: t(2, 2), t3(3, 3)
    integer(c_int) :: p
    status = check_size(ns)
    if (status /= BW_LAW_OK) return
    call make_law(par, with_cap, law, status)
    if (status /= BW_LAW_OK) return
    do p = 1, n
      status = check_portion_ns(ns, state_in(:, p), jump(:, p))
      if (status /= BW_LAW_OK) return
      if (ns == 2) then
        call portion_2d(law, state_in(:, p), jump(:, p), stress(:, p), t, state_out(:, p), mode(p), status)
        tangent(:, p) = [t(1, 1), t(1, 2), t(2, 1), t(2, 2)]
      else
        call portion_3d(law, state_in(:, p), jump(:, p), stress(:, p), t3, state_out(:, p), mode(p), status)
        tangent(:, p) = [t3(1, :), t3(2, :), t3(3, :)]
      end if
      if (status /= BW_LAW_OK) return
    end do
  end subroutine plastic_kernel

  !> Tension cut-off and Coulomb friction with softening: the return mapping above,
  !> in 3D on the meridian plane of the circular cone. The cap's parameters are not read.
  pure subroutine bw_law_coulomb(ns, n, par, state_in, jump, stress, tangent, state_out, mode, status) &
       bind(C, name="bw_law_coulomb")
    integer(c_int), value, intent(in) :: ns, n
    real(c_double), intent(in) :: par(NPAR), state_in(ns + 3, n), jump(ns, n)
    real(c_double), intent(out) :: stress(ns, n), tangent(ns * ns, n), state_out(ns + 3, n)
    integer(c_signed_char), intent(out) :: mode(n)
    integer(c_int), intent(out) :: status
    call plastic_kernel(.false., ns, n, par, state_in, jump, stress, tangent, state_out, mode, status)
  end subroutine bw_law_coulomb

  !> The same with the compressive cap (model.md, "Compressive cap").
  pure subroutine bw_law_coulomb_cap(ns, n, par, state_in, jump, stress, tangent, state_out, mode, status) &
       bind(C, name="bw_law_coulomb_cap")
    integer(c_int), value, intent(in) :: ns, n
    real(c_double), intent(in) :: par(NPAR), state_in(ns + 3, n), jump(ns, n)
    real(c_double), intent(out) :: stress(ns, n), tangent(ns * ns, n), state_out(ns + 3, n)
    integer(c_signed_char), intent(out) :: mode(n)
    integer(c_int), intent(out) :: status
    call plastic_kernel(.true., ns, n, par, state_in, jump, stress, tangent, state_out, mode, status)
  end subroutine bw_law_coulomb_cap

end module bw_joint_law_kernels
