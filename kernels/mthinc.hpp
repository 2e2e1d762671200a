// MTHINC: multi-dimensional THINC (Ii, Sugiyama, Takeuchi, Takagi & Matsumoto,
// JCP 2012). Inside an interface cell the volume fraction is a tanh step
// across a plane,
//   H(X) = (1 + tanh(beta (n . X + d))) / 2,   X in [-1/2, 1/2]^3 (cell units),
// n the unit normal (towards the solid), d set so that H's cell mean is the
// cell's value. A face's flux value is H's mean over the part of the upwind
// cell that crosses the face in the stage, as in thinc_right_swept.
// Why not direction by direction (kernels/thinc.hpp): a 1-D step along x of a
// plane tilted from x is 1/|n_x| wider than along its normal, but 1-D THINC
// gives it the same steepness beta in every direction. The compression then
// depends on the interface's orientation, and a sphere turning about a tilted
// axis drifts to an ellipsoid (tests/test_solid.cpp, the tilted-axis test).
// Here the step has one steepness, along the normal, whatever the orientation.
// The integrals: analytic (ln cosh) along the normal's largest component, 2x2
// Gauss-Legendre across it; d by safeguarded Newton on the same quadrature,
// so the cell mean of the reconstruction is the cell's value to 1e-13.
// Point-wise and backend-neutral, unit-tested on the host (tests/test_mthinc.cpp).
#pragma once
#include <cmath>

#include "../src/types.hpp"

namespace softflow {

// The plane of one cell; dom < 0: no interface there (the flux takes the
// cell's value, first-order upwind)
struct MthincPlane {
  Real n[3];
  Real d;
  int dom;  // the axis of n's largest component: integrated analytically
};

// cells within this of 0 or 1 carry no interface: phi's cut-off
// (phi_zero_cut, kernels/solid_transport.hpp), so every cell the transport
// keeps non-zero gets its plane. A larger value (1e-6 was tried) hands the
// tails to first-order upwinding, which spreads them: a haze of phi ~1e-9
// reached cells 8 away from a particle turning for 50 time units, and the
// dilute runs' active region grew to the whole box.
constexpr Real mthinc_eps = 1e-10;

// ln cosh x without overflow
KOKKOS_INLINE_FUNCTION Real log_cosh(Real x) {
  const Real a = Kokkos::fabs(x);
  return a + Kokkos::log1p(Kokkos::exp(-2 * a)) - Real(0.69314718055994530942);
}

// Mean of tanh(beta (nD X + c)) over X in [a, b], and (with slope) its
// derivative in c: with x = beta (nD X + c) and e = exp(-2|x|) at each end,
// ln cosh x = |x| + log1p(e) - ln 2 and tanh x = sign(x) (1 - e) / (1 + e),
// one exp and one log1p per end. Below a span of 1e-4 the midpoint value
// (error < 4e-10; the ln cosh difference would lose digits there).
KOKKOS_INLINE_FUNCTION Real mean_tanh_1d(Real beta, Real nD, Real c, Real a, Real b, Real* slope) {
  const Real span = beta * nD * (b - a);
  if (Kokkos::fabs(span) < Real(1e-4)) {
    const Real t = Kokkos::tanh(beta * (nD * (a + b) / 2 + c));
    if (slope) *slope = beta * (1 - t * t);
    return t;
  }
  const Real xa = beta * (nD * a + c), xb = beta * (nD * b + c);
  const Real ua = Kokkos::fabs(xa), ub = Kokkos::fabs(xb);
  const Real ea = Kokkos::exp(-2 * ua), eb = Kokkos::exp(-2 * ub);
  if (slope) {
    const Real ta = (xa < 0 ? -1 : 1) * (1 - ea) / (1 + ea), tb = (xb < 0 ? -1 : 1) * (1 - eb) / (1 + eb);
    *slope = (tb - ta) / (nD * (b - a));
  }
  return (ub - ua + Kokkos::log1p(eb) - Kokkos::log1p(ea)) / span;
}

// Mean of H over the box lo..hi inside the cell (and, with dmean, its
// derivative in d). Across the normal's largest component: 2x2 Gauss-Legendre
// (exact for cubics). Against the exact means (tests/test_mthinc.cpp): within
// 3.5e-3 for a cell, 7e-3 for a thin swept slab; 3x3 points are 10 times
// closer but cost 2.6 times as much, and gave the same tilted-axis turn to 4
// digits. The fit uses the same quadrature, so the scheme stays conservative
// and bounded whatever its error.
KOKKOS_INLINE_FUNCTION Real mthinc_box_mean(const MthincPlane& p, Real beta, const Real lo[3],
                                            const Real hi[3], Real* dmean = nullptr) {
  const int D = p.dom, t1 = (D + 1) % 3, t2 = (D + 2) % 3;
  const Real gx[2] = {Real(-0.57735026918962576451), Real(0.57735026918962576451)};  // on [-1, 1]
  const Real m1 = (lo[t1] + hi[t1]) / 2, h1 = (hi[t1] - lo[t1]) / 2;
  const Real m2 = (lo[t2] + hi[t2]) / 2, h2 = (hi[t2] - lo[t2]) / 2;
  Real sum = 0, dsum = 0;
  for (int a = 0; a < 2; ++a)
    for (int b = 0; b < 2; ++b) {
      const Real c = p.n[t1] * (m1 + h1 * gx[a]) + p.n[t2] * (m2 + h2 * gx[b]) + p.d;
      Real s = 0;
      sum += mean_tanh_1d(beta, p.n[D], c, lo[D], hi[D], dmean ? &s : nullptr);
      dsum += s;
    }
  if (dmean) *dmean = dsum / 8;  // the 4 nodes' mean, halved
  return (1 + sum / 4) / 2;
}

// The plane of a cell of value q whose (unnormalised) phi gradient is g
KOKKOS_INLINE_FUNCTION MthincPlane mthinc_fit(Real q, const Real g[3], Real beta) {
  MthincPlane p{{0, 0, 0}, 0, -1};
  const Real norm = Kokkos::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!(q > mthinc_eps && q < 1 - mthinc_eps) || norm < Real(1e-12)) return p;
  for (int a = 0; a < 3; ++a) p.n[a] = g[a] / norm;
  p.dom = 0;
  for (int a = 1; a < 3; ++a)
    if (Kokkos::fabs(p.n[a]) > Kokkos::fabs(p.n[p.dom])) p.dom = a;
  const Real lo[3] = {Real(-0.5), Real(-0.5), Real(-0.5)}, hi[3] = {Real(0.5), Real(0.5), Real(0.5)};
  // |n . X| <= sqrt(3)/2 in the cell, and tanh(beta d) = +-(1 - 2 eps) needs
  // |d| < 11.6 / beta: the root lies in [-bound, bound]
  Real dl = -(1 + 13 / beta), dh = 1 + 13 / beta;
  // start from the root of the grid-aligned plane (1-D THINC's, closed form:
  // e^{2 beta d} = (e^{2 beta q} - 1) / (e^beta (1 - e^{2 beta (q - 1)}))):
  // 3 evaluations on average from there, 8 from d = 0
  p.d = (Kokkos::log(Kokkos::expm1(2 * beta * q)) - beta - Kokkos::log(-Kokkos::expm1(2 * beta * (q - 1)))) /
        (2 * beta);
  p.d = p.d < dl ? dl : (p.d > dh ? dh : p.d);
  for (int it = 0; it < 60; ++it) {
    Real slope = 0;
    const Real f = mthinc_box_mean(p, beta, lo, hi, &slope) - q;
    if (Kokkos::fabs(f) < Real(1e-14)) break;
    if (f < 0)
      dl = p.d;
    else
      dh = p.d;
    Real next = slope > 0 ? p.d - f / slope : dl - 1;
    const bool newton = next > dl && next < dh;
    if (!newton) next = (dl + dh) / 2;  // Newton left the bracket: bisect
    const Real step = next - p.d;
    p.d = next;
    // a Newton step this small leaves an error of about beta step^2 < 1e-13:
    // no need to evaluate again (saves one of four evaluations)
    if ((newton && Kokkos::fabs(step) < Real(1e-7)) || dh - dl < Real(1e-15)) break;
  }
  return p;
}

// Flux value at a face of a cell along axis `ax`: H's mean over the slab of
// width nu next to the face (`high`: the +1/2 face). A cell without an
// interface gives its own value q.
KOKKOS_INLINE_FUNCTION Real mthinc_face_value(const MthincPlane& p, Real q, Real beta, int ax, bool high,
                                              Real nu) {
  if (p.dom < 0) return q;
  nu = nu < 1 ? nu : Real(1);
  Real lo[3] = {Real(-0.5), Real(-0.5), Real(-0.5)}, hi[3] = {Real(0.5), Real(0.5), Real(0.5)};
  if (high)
    lo[ax] = Real(0.5) - nu;
  else
    hi[ax] = Real(-0.5) + nu;
  return mthinc_box_mean(p, beta, lo, hi);
}

}  // namespace softflow
