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
  Real qmin, dq, theta, A;  // A = -tanh(beta X0)
  bool interface;           // false: use the cell value
};

// The step of cell c from its left neighbour qm, value qc and right neighbour qp
KOKKOS_INLINE_FUNCTION ThincStep thinc_step(Real qm, Real qc, Real qp, const Thinc& t) {
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
  const Real B = Kokkos::exp(s.theta * t.beta * (2 * C - 1));
  s.A = (B / t.cosh_beta - 1) / t.tanh_beta;
  return s;
}

// Value at the right face (X = 1) of cell c
KOKKOS_INLINE_FUNCTION Real thinc_right(Real qm, Real qc, Real qp, const Thinc& t) {
  const ThincStep s = thinc_step(qm, qc, qp, t);
  if (!s.interface) return qc;
  const Real tb = t.tanh_beta;
  return s.qmin + s.dq / 2 * (1 + s.theta * (tb + s.A) / (1 + s.A * tb));
}

// Value at the left face (X = 0) of cell c
KOKKOS_INLINE_FUNCTION Real thinc_left(Real qm, Real qc, Real qp, const Thinc& t) {
  const ThincStep s = thinc_step(qm, qc, qp, t);
  if (!s.interface) return qc;
  return s.qmin + s.dq / 2 * (1 + s.theta * s.A);
}

// Upwind THINC value at face c+1/2 from the four cells c-1..c+2 and the face
// velocity: the right face of cell c for vel >= 0, else the left face of c+1.
// The cells are chosen first and the step evaluated once (no branch around
// the arithmetic, as in weno5_face).
KOKKOS_INLINE_FUNCTION Real thinc_face(Real vel, Real qm1, Real q0, Real qp1, Real qp2, const Thinc& t) {
  const bool left = vel >= 0;
  // mirrored for vel < 0: the right face of the mirrored cell c+1
  return thinc_right(left ? qm1 : qp2, left ? q0 : qp1, left ? qp1 : q0, t);
}

}  // namespace softflow
