/* Double-double numbers (value = hi + lo, |lo| <= ulp(hi) / 2: about 32
 * digits) for the few sums that must be computed far below double's
 * round-off (the extra-precise residual of solver/estimates.c). Knuth's
 * two-sum and Dekker's two-product, both exact in IEEE double without a
 * fused multiply-add (C's fma() is a library call on a build for the
 * baseline x86-64: 30 % of the residual's time). The per-interface kernels
 * have their own (Fortran, interface_kernels.f90). */
#pragma once

typedef struct {
  double hi, lo;
} BwDD;

static inline BwDD BwDDTwoSum(double a, double b)
{
  double s = a + b, bb = s - a;
  return (BwDD){s, (a - (s - bb)) + (b - bb)};
}

/* a b exactly: p + e (the file that includes this header is compiled
 * with -ffp-contract=off: src/CMakeLists.txt) */
static inline BwDD BwDDProd(double a, double b)
{
  const double split = 134217729.0; /* 2^27 + 1 */
  double       p = a * b, c = split * a, ah = c - (c - a), al = a - ah, bh, bl;
  c  = split * b;
  bh = c - (c - b);
  bl = b - bh;
  return (BwDD){p, ((ah * bh - p) + ah * bl + al * bh) + al * bl};
}

/* a + b */
static inline BwDD BwDDAdd(BwDD a, BwDD b)
{
  BwDD s = BwDDTwoSum(a.hi, b.hi);
  return BwDDTwoSum(s.hi, s.lo + (a.lo + b.lo));
}

/* x y, x a double */
static inline BwDD BwDDScale(double x, BwDD y)
{
  BwDD p = BwDDProd(x, y.hi);
  return BwDDTwoSum(p.hi, p.lo + x * y.lo);
}
