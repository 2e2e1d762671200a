// THINC reconstruction (Xiao, Honma & Kono 2005; the form of Deng, Xie &
// Xiao, JCP 2018) of a volume fraction at a cell face, from the upwind cell.
// Inside an interface cell the volume fraction is taken as a tanh step
//   q(X) = q_min + (q_max - q_min) / 2 (1 + theta tanh(beta (X - X0))),
// X in [0, 1] across the cell, theta the side the larger neighbour is on, and
// X0 set so that the step's cell average is the cell's value. beta sets the
// steepness: the step spans about 2 / beta cells, so the interface stays one
// to two cells thick however long it is advected (WENO5 smears a
// tank-treading particle's interface by a cell every few strain units).
// Cells that are not between their two neighbours (no interface, or a sliver)
// give their own value (first-order upwind), as in THINC/SW.
// Point-wise and backend-neutral, unit-tested on the host (tests/test_thinc.cpp).
#pragma once
#include <cmath>

#include "../src/types.hpp"

namespace softflow {

// beta with its tanh and cosh, computed once on the host (a kernel would
// otherwise call both per face)
struct Thinc {
  Real beta, tanh_beta, cosh_beta;
};
inline Thinc make_thinc(Real beta) { return {beta, std::tanh(beta), std::cosh(beta)}; }

struct ThincStep {
  Real qmin, dq, theta;
  Real z;          // theta (2C - 1), C the cell's share of the jump: B = exp(beta z)
  bool interface;  // false: use the cell value
};

// The step of cell c from its left neighbour qm, value qc and right neighbour qp
KOKKOS_INLINE_FUNCTION ThincStep thinc_step(Real qm, Real qc, Real qp) {
  constexpr Real eps = 1e-20;
  ThincStep s{0, 0, 0, 0, false};
  const Real lo = qm < qp ? qm : qp, hi = qm < qp ? qp : qm;
  s.qmin = lo;
  s.dq = hi - lo;
  // monotone through the cell, and a jump large enough to be an interface
  s.interface = (qp - qc) * (qc - qm) > 0 && s.dq > Real(1e-12);
  if (!s.interface) return s;
  s.theta = qp >= qm ? Real(1) : Real(-1);
  const Real C = (qc - lo + eps) / (s.dq + eps);
  s.z = s.theta * (2 * C - 1);
  return s;
}

// A = -tanh(beta X0) of an interface step (the point values need it; the
// swept mean does not, and skips its exp)
KOKKOS_INLINE_FUNCTION Real thinc_A(const ThincStep& s, const Thinc& t) {
  return (Kokkos::exp(t.beta * s.z) / t.cosh_beta - 1) / t.tanh_beta;
}

// Value at the right face (X = 1) of cell c
KOKKOS_INLINE_FUNCTION Real thinc_right(Real qm, Real qc, Real qp, const Thinc& t) {
  const ThincStep s = thinc_step(qm, qc, qp);
  if (!s.interface) return qc;
  const Real tb = t.tanh_beta;
  const Real A = thinc_A(s, t);
  return s.qmin + s.dq / 2 * (1 + s.theta * (tb + A) / (1 + A * tb));
}

// Value at the left face (X = 0) of cell c
KOKKOS_INLINE_FUNCTION Real thinc_left(Real qm, Real qc, Real qp, const Thinc& t) {
  const ThincStep s = thinc_step(qm, qc, qp);
  if (!s.interface) return qc;
  return s.qmin + s.dq / 2 * (1 + s.theta * thinc_A(s, t));
}

// Mean of the step over the part of cell c that crosses its right face in a
// step of Courant number nu = |u| dt / dx, X in [1 - nu, 1]: THINC's own
// flux (Xiao, Honma & Kono 2005). The point value at X = 1 (nu -> 0) is
// what a method-of-lines flux would take, but it lets a cell receive more
// than it can hold: at beta = 3.5 and Courant number 0.4 a square wave
// over- and undershoots by 0.7% a step, and the clip that keeps phi in
// [0, 1] then moves volume from the front of the wave to its back, so it
// lags by a fixed distance at every resolution (L1 error 0.05 at 32, 64 and
// 128 cells, tests/test_thinc.cpp). The swept mean gives a cell's downwind
// face no more than the cell holds there, so the scheme stays bounded and
// first order at any Courant number up to 1.
// Closed form: with z = theta (2C - 1) (so B = exp(beta z)), P = e^{beta (1 +
// z)} - 1 and Q = 1 - e^{beta (z - 1)} (both > 0, as |z| < 1), w = P / (P + Q)
// and s = beta nu,
//   mean of tanh(beta (X - X0)) over [1 - nu, 1] = -ln(w e^{-s} + (1 - w) e^{s}) / s,
// which tends to the point value 2w - 1 as s -> 0. Written with expm1 and
// log1p it loses no digits for small nu, nor for cells that are all but full
// or empty (where X0, and cosh(beta) + A sinh(beta), lose all of theirs).
KOKKOS_INLINE_FUNCTION Real thinc_right_swept(Real qm, Real qc, Real qp, const Thinc& t, Real nu) {
  const ThincStep st = thinc_step(qm, qc, qp);
  if (!st.interface) return qc;
  const Real P = Kokkos::expm1(t.beta * (1 + st.z)), Q = -Kokkos::expm1(t.beta * (st.z - 1));
  const Real w = P / (P + Q);
  const Real s = t.beta * (nu < 1 ? nu : Real(1));
  const Real mean_tanh =
      s > Real(1e-300) ? -Kokkos::log1p(w * Kokkos::expm1(-s) + (1 - w) * Kokkos::expm1(s)) / s : 2 * w - 1;
  return st.qmin + st.dq / 2 * (1 + st.theta * mean_tanh);
}

// Upwind THINC flux value at face c+1/2 from the four cells c-1..c+2, the
// face velocity and the Courant number of the stage at that face: the swept
// mean at the right face of cell c for vel >= 0, else at the left face of
// c+1. The cells are chosen first and the step evaluated once (no branch
// around the arithmetic, as in weno5_face).
KOKKOS_INLINE_FUNCTION Real thinc_face(Real vel, Real qm1, Real q0, Real qp1, Real qp2, const Thinc& t,
                                       Real nu) {
  const bool left = vel >= 0;
  // mirrored for vel < 0: the right face of the mirrored cell c+1
  return thinc_right_swept(left ? qm1 : qp2, left ? q0 : qp1, left ? qp1 : q0, t, nu);
}

}  // namespace softflow
