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
// The integrals: analytic along the normal's largest component, 2x2
// Gauss-Legendre across it (exact for cubics; against the exact means, within
// 3.5e-3 for a cell and 7e-3 for a thin swept slab, tests/test_mthinc.cpp;
// 3x3 nodes were 10 times closer, cost 2.6 times as much and gave the same
// tilted-axis turn to 4 digits); d by safeguarded Newton on the same
// quadrature, so the cell mean of the reconstruction is the cell's value to
// 1e-13. The volume is conserved whatever the quadrature's error (the fluxes
// telescope); a face flux along the normal's largest component never takes
// more than the cell holds, one across it at most the quadrature error more
// (the clip of phi to [0, 1] takes that, tests/test_mthinc.cpp).
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

// The exponentials of a fitted plane that every face value of its cell
// shares, kept with the plane so that a face takes one or two exps and two
// logs instead of six and two (the face values were half of MTHINC's cost):
// E = exp(-2 beta d); e1, e2 = exp(-beta n_t g) across the dominant axis D
// (t1 = D + 1, t2 = D + 2 cyclically, g = 1/sqrt(3), the full cell's Gauss
// nodes); eD = exp(-beta |n_D|).
struct MthincExps {
  Real E, e1, e2, eD;
};

// cells within this of 0 or 1 carry no interface: phi's cut-off
// (phi_zero_cut, kernels/solid_transport.hpp), so every cell the transport
// keeps non-zero gets its plane. A larger value (1e-6 was tried) hands the
// tails to first-order upwinding, which spreads them: a haze of phi ~1e-9
// reached cells 8 away from a particle turning for 50 time units, and the
// dilute runs' active region grew to the whole box.
constexpr Real mthinc_eps = 1e-10;
KOKKOS_INLINE_FUNCTION bool mthinc_interface(Real q) { return q > mthinc_eps && q < 1 - mthinc_eps; }

// the axis of n's largest component (the first of equal ones)
KOKKOS_INLINE_FUNCTION int dominant_axis(const Real n[3]) {
  const Real a0 = Kokkos::fabs(n[0]), a1 = Kokkos::fabs(n[1]), a2 = Kokkos::fabs(n[2]);
  return a0 >= a1 ? (a0 >= a2 ? 0 : 2) : (a1 >= a2 ? 1 : 2);
}

// H = (1 + tanh x) / 2 = 1 / (1 + u), u = exp(-2x), x = beta (n . X + d).
// With the axis D of n's largest component turned so that nD > 0, H's mean
// along D over [a, b] at a node of transverse offset s is
//   1 + ln[(1 + u(b)) / (1 + u(a))] / (2 beta nD (b - a)),
// and u = exp(-2 beta nD X_D) exp(-2 beta n1 Y) exp(-2 beta n2 Z) exp(-2 beta d)
// separates. So the mean over 2x2 Gauss-Legendre nodes across D is
//   1 + ln[prod_g (1 + u_g(b)) / prod_g (1 + u_g(a))] / (8 beta nD (b - a)):
// a few exps and two logs per box, where one ln cosh per node and end would
// take sixteen. The products are kept as prod - 1 (prod_next - 1 =
// (prod - 1)(1 + u) + u), so a cell that is all but full loses no digits,
// and their logs taken apart (the log of their ratio, near 0 in an all but
// empty cell, would lose half of them).

// prod (1 + k_g e) - 1 over the 4 nodes' factors k
KOKKOS_INLINE_FUNCTION Real prod_one_plus_minus_one(const Real k[4], Real e) {
  Real m = 0;
  for (int g = 0; g < 4; ++g) m = m * (1 + k[g] * e) + k[g] * e;
  return m;
}

constexpr Real mthinc_gauss = Real(0.57735026918962576451);  // the nodes at +-1/sqrt(3) of the half-width

// The 4 nodes' factors c e1^+-1 e2^+-1
KOKKOS_INLINE_FUNCTION void mthinc_nodes(Real c, Real e1, Real e2, Real k[4]) {
  k[0] = c * e1 * e2, k[1] = c * e1 / e2, k[2] = c / e1 * e2, k[3] = c / (e1 * e2);
}

// H's mean along D over [a, b] (in the frame where n_D = nD > 0) at the
// nodes of factors k; ea, eb = exp(-2 beta nD a), exp(-2 beta nD b). Below a
// span 2 beta nD (b - a) of 1e-4 the nodes' midpoint values (error < 1e-9;
// the log of the ratio would lose digits there).
KOKKOS_INLINE_FUNCTION Real mthinc_mean_along(const Real k[4], Real beta, Real nD, Real a, Real b, Real ea,
                                              Real eb) {
  const Real span = 2 * beta * nD * (b - a);
  if (span < Real(1e-4)) {
    const Real e = Kokkos::exp(-beta * nD * (a + b));
    Real h = 0;
    for (int g = 0; g < 4; ++g) h += 1 / (1 + k[g] * e);
    return h / 4;
  }
  const Real ma = prod_one_plus_minus_one(k, ea), mb = prod_one_plus_minus_one(k, eb);
  return 1 + (Kokkos::log1p(mb) - Kokkos::log1p(ma)) / (4 * span);
}

// Mean of H over the box lo..hi inside the cell (any box: the fit's test
// uses it; the transport's faces take mthinc_face_value)
KOKKOS_INLINE_FUNCTION Real mthinc_box_mean(const MthincPlane& p, Real beta, const Real lo[3],
                                            const Real hi[3]) {
  const int D = p.dom, t1 = (D + 1) % 3, t2 = (D + 2) % 3;
  const bool flip = p.n[D] < 0;
  const Real nD = flip ? -p.n[D] : p.n[D];
  const Real a = flip ? -hi[D] : lo[D], b = flip ? -lo[D] : hi[D];
  const Real c =
      Kokkos::exp(-2 * beta * p.d - beta * (p.n[t1] * (lo[t1] + hi[t1]) + p.n[t2] * (lo[t2] + hi[t2])));
  Real k[4];
  mthinc_nodes(c, Kokkos::exp(-beta * p.n[t1] * (hi[t1] - lo[t1]) * mthinc_gauss),
               Kokkos::exp(-beta * p.n[t2] * (hi[t2] - lo[t2]) * mthinc_gauss), k);
  return mthinc_mean_along(k, beta, nD, a, b, Kokkos::exp(-2 * beta * nD * a),
                           Kokkos::exp(-2 * beta * nD * b));
}

// The plane of a cell of value q whose (unnormalised) phi gradient is g.
// With E = exp(-2 beta d) = e^t and the full cell's nodes, q = 1 + Phi(t) /
// (8 beta nD), Phi(t) = ln[prod (1 + al_g E) / prod (1 + ga_g E)], al_g and ga_g
// the factors at X_D = 1/2 and -1/2: Newton on t, an exp and two logs a step.
// x: the exps the cell's face values share.
KOKKOS_INLINE_FUNCTION MthincPlane mthinc_fit(Real q, const Real g[3], Real beta, MthincExps& x) {
  MthincPlane p{{0, 0, 0}, 0, -1};
  x = MthincExps{1, 1, 1, 1};
  const Real norm = Kokkos::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!mthinc_interface(q) || norm < Real(1e-12)) return p;
  for (int a = 0; a < 3; ++a) p.n[a] = g[a] / norm;
  p.dom = dominant_axis(p.n);
  const Real nD = Kokkos::fabs(p.n[p.dom]);
  x.e1 = Kokkos::exp(-beta * p.n[(p.dom + 1) % 3] * mthinc_gauss);
  x.e2 = Kokkos::exp(-beta * p.n[(p.dom + 2) % 3] * mthinc_gauss);
  x.eD = Kokkos::exp(-beta * nD);
  Real al[4], ga[4];
  mthinc_nodes(x.eD, x.e1, x.e2, al);
  const Real e2D = 1 / (x.eD * x.eD);
  for (int k = 0; k < 4; ++k) ga[k] = al[k] * e2D;
  const Real target = 8 * beta * nD * (q - 1);
  // |n . X| <= sqrt(3)/2 in the cell, and tanh(beta d) = +-(1 - 2 eps) needs
  // |d| < 11.6 / beta: the root lies in d in [-bound, bound], t = -2 beta d
  const Real bound = 2 * beta * (1 + 13 / beta);
  Real tl = -bound, th = bound;
  // start from the root of the grid-aligned plane (1-D THINC's, closed form:
  // e^{2 beta d} = (e^{2 beta q} - 1) / (e^beta (1 - e^{2 beta (q - 1)}))):
  // about 3 steps from there
  Real t =
      -(Kokkos::log(Kokkos::expm1(2 * beta * q)) - beta - Kokkos::log(-Kokkos::expm1(2 * beta * (q - 1))));
  t = t < tl ? tl : (t > th ? th : t);
  for (int it = 0; it < 80; ++it) {
    const Real E = Kokkos::exp(t);
    const Real mn = prod_one_plus_minus_one(al, E), md = prod_one_plus_minus_one(ga, E);
    const Real f = Kokkos::log1p(mn) - Kokkos::log1p(md) - target;  // decreasing in t
    if (Kokkos::fabs(f) < 8 * beta * nD * Real(1e-14)) break;
    if (f > 0)
      tl = t;
    else
      th = t;
    // dPhi/dt = sum (al - ga) E / ((1 + al E)(1 + ga E)), without cancellation
    Real slope = 0;
    for (int k = 0; k < 4; ++k) slope += (al[k] - ga[k]) * E / ((1 + al[k] * E) * (1 + ga[k] * E));
    Real next = slope < 0 ? t - f / slope : th + 1;
    const bool newton = next > tl && next < th;
    if (!newton) next = (tl + th) / 2;  // Newton left the bracket: bisect
    const Real step = next - t;
    t = next;
    // a Newton step this small leaves an error in d of about 1e-14
    if ((newton && Kokkos::fabs(step) < Real(1e-7)) || th - tl < Real(1e-14)) break;
  }
  p.d = -t / (2 * beta);
  x.E = Kokkos::exp(t);
  return p;
}
KOKKOS_INLINE_FUNCTION MthincPlane mthinc_fit(Real q, const Real g[3], Real beta) {
  MthincExps x;
  return mthinc_fit(q, g, beta, x);
}

// Flux value at a face of a cell along axis `ax`: H's mean over the slab of
// width nu next to the face (`high`: the +1/2 face), from the plane and its
// exps. A cell without an interface gives its own value q.
KOKKOS_INLINE_FUNCTION Real mthinc_face_value(const MthincPlane& p, const MthincExps& x, Real q, Real beta,
                                              int ax, bool high, Real nu) {
  if (p.dom < 0) return q;
  nu = nu < 1 ? nu : Real(1);
  const int D = p.dom;
  const bool flip = p.n[D] < 0;
  const Real nD = flip ? -p.n[D] : p.n[D];
  Real k[4];
  if (ax == D) {  // the full cell across D; along it the slab touches X_D = 1/2 or -1/2 (after the flip)
    mthinc_nodes(x.E, x.e1, x.e2, k);
    if (high != flip) {
      const Real a = Real(0.5) - nu;
      return mthinc_mean_along(k, beta, nD, a, Real(0.5), Kokkos::exp(-2 * beta * nD * a), x.eD);
    }
    const Real b = Real(-0.5) + nu;
    return mthinc_mean_along(k, beta, nD, Real(-0.5), b, 1 / x.eD, Kokkos::exp(-2 * beta * nD * b));
  }
  // the slab across D: its centre at +-(1 - nu)/2 and its width nu along ax
  const Real nt = p.n[ax];
  const Real c = x.E * Kokkos::exp(-beta * nt * (high ? 1 - nu : nu - 1));
  const Real es = Kokkos::exp(-beta * nt * nu * mthinc_gauss);
  if (ax == (D + 1) % 3)
    mthinc_nodes(c, es, x.e2, k);
  else
    mthinc_nodes(c, x.e1, es, k);
  return mthinc_mean_along(k, beta, nD, Real(-0.5), Real(0.5), 1 / x.eD, x.eD);
}

}  // namespace softflow
