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

// The tails: in a cell with q below mthinc_tail, H = 1 / (1 + u) is 1 / u to a
// relative 1/u <= max H over the cell, which is at most about 9 q at beta =
// 3.5 (an exponential's mean across the cell is no less than about 1/9 of its
// largest value), so a value differs from the full form's by about 81 q^2 at
// most: 5e-13 measured at q = 1e-7 (tests/test_mthinc.cpp); near 1 the same
// for 1 - H and u. Both are exponentials, whose means have closed forms: the fit
// needs no Newton, and a face value no log (the full form's 1 + ln(...) also
// loses the relative digits of a tiny value). About a third of the cells
// fitted are tails (phi's tanh profile takes 3.3 cells to fall from 1/2 to
// mthinc_eps, 1 of them below 1e-7).
constexpr Real mthinc_tail = 1e-7;
// -1: the empty tail, +1: the full one, 0: neither
KOKKOS_INLINE_FUNCTION int mthinc_side(Real q) {
  return q < mthinc_tail ? -1 : (q > 1 - mthinc_tail ? 1 : 0);
}

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
                                              Real eb, int side) {
  const Real span = 2 * beta * nD * (b - a);
  if (span < Real(1e-4)) {
    const Real e = Kokkos::exp(-beta * nD * (a + b));
    Real h = 0;
    for (int g = 0; g < 4; ++g) h += 1 / (1 + k[g] * e);
    return h / 4;
  }
  if (side != 0) {  // the tails: the mean of 1 / u, or 1 minus that of u
    Real sk = 0;
    for (int g = 0; g < 4; ++g) sk += side < 0 ? 1 / k[g] : k[g];
    return side < 0 ? sk / 4 * (1 / eb - 1 / ea) / span : 1 - sk / 4 * (ea - eb) / span;
  }
  // ln[(1 + mb) / (1 + ma)] with one log: near 0 (ratio above 1/2) as log1p of
  // (mb - ma) / (1 + ma), whose difference loses nothing there
  const Real ma = prod_one_plus_minus_one(k, ea), mb = prod_one_plus_minus_one(k, eb);
  const Real ratio = (1 + mb) / (1 + ma);
  const Real lr = ratio > Real(0.5) ? Kokkos::log1p((mb - ma) / (1 + ma)) : Kokkos::log(ratio);
  return 1 + lr / (4 * span);
}

// Mean of H over the box lo..hi inside the cell (any box: the fit's test
// uses it; the transport's faces take mthinc_face_value)
KOKKOS_INLINE_FUNCTION Real mthinc_box_mean(const MthincPlane& p, const MthincExps& x, Real q, Real beta,
                                            const Real lo[3], const Real hi[3]) {
  const int D = p.dom, t1 = (D + 1) % 3, t2 = (D + 2) % 3;
  const bool flip = p.n[D] < 0;
  const Real nD = flip ? -p.n[D] : p.n[D];
  const Real a = flip ? -hi[D] : lo[D], b = flip ? -lo[D] : hi[D];
  const Real c = x.E * Kokkos::exp(-beta * (p.n[t1] * (lo[t1] + hi[t1]) + p.n[t2] * (lo[t2] + hi[t2])));
  Real k[4];
  mthinc_nodes(c, Kokkos::exp(-beta * p.n[t1] * (hi[t1] - lo[t1]) * mthinc_gauss),
               Kokkos::exp(-beta * p.n[t2] * (hi[t2] - lo[t2]) * mthinc_gauss), k);
  return mthinc_mean_along(k, beta, nD, a, b, Kokkos::exp(-2 * beta * nD * a),
                           Kokkos::exp(-2 * beta * nD * b), mthinc_side(q));
}

// The plane of a cell of value q whose (unnormalised) phi gradient is g, and
// in x the exps its face values share. With E = exp(-2 beta d) and the full
// cell's nodes, q = 1 + ln[P_al(E) / P_ga(E)] / (8 beta nD), P_k(E) =
// prod (1 + k_g E), al_g and ga_g the factors at X_D = 1/2 and -1/2. So E is
// the positive root of the quartic
//   F(E) = P_al(E) - R P_ga(E),   R = exp(8 beta nD (q - 1)),
// found by Newton on ln(P_al / (R P_ga)) in ln E, which is nearly linear:
// one log1p a step far from the root, none near it (its series), and exp of
// the step by a Pade approximant (the earlier Newton on ln P_al - ln P_ga
// took an exp and two logs every step, and the fit was MTHINC's largest
// kernel). F > 0 below the root and < 0 above it, so the root stays
// bracketed; a step that leaves the bracket is replaced by the bracket's
// geometric midpoint. Tail cells take a closed form instead (above). d itself
// is not needed by the transport (mthinc_offset gives it).
// e_beta = exp(beta), the same for every cell: the transport's kernel takes
// it once (mthinc_fit(q, g, beta, x) below takes it per call)
KOKKOS_INLINE_FUNCTION MthincPlane mthinc_fit(Real q, const Real g[3], Real beta, Real e_beta, MthincExps& x) {
  MthincPlane p{{0, 0, 0}, -1};
  x = MthincExps{1, 1, 1, 1};
  const Real norm = Kokkos::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  if (!mthinc_interface(q) || norm < Real(1e-12)) return p;
  for (int a = 0; a < 3; ++a) p.n[a] = g[a] / norm;
  p.dom = dominant_axis(p.n);
  const Real nD = Kokkos::fabs(p.n[p.dom]);
  x.e1 = Kokkos::exp(-beta * p.n[(p.dom + 1) % 3] * mthinc_gauss);
  x.e2 = Kokkos::exp(-beta * p.n[(p.dom + 2) % 3] * mthinc_gauss);
  x.eD = Kokkos::exp(-beta * nD);
  const int side = mthinc_side(q);
  if (side != 0) {
    // the mean of exp(-2 beta (n . X)) over the cell's nodes: E times it is
    // 1 - q (full tail), or 1 / E times that of its inverse, the same, is q
    const Real c = (x.e1 + 1 / x.e1) * (x.e2 + 1 / x.e2) / 4 * (1 / x.eD - x.eD) / (2 * beta * nD);
    x.E = side < 0 ? c / q : (1 - q) / c;
    return p;
  }
  Real al[4], ga[4];
  mthinc_nodes(x.eD, x.e1, x.e2, al);
  const Real e2D = 1 / (x.eD * x.eD);
  for (int k = 0; k < 4; ++k) ga[k] = al[k] * e2D;
  // R and 1 - R, each without cancellation
  const Real target = 8 * beta * nD * (q - 1);
  Real R, omR;
  if (target < Real(-0.6931471805599453)) {
    R = Kokkos::exp(target), omR = 1 - R;
  } else {
    omR = -Kokkos::expm1(target), R = 1 - omR;
  }
  // |n . X| <= sqrt(3)/2 in the cell, and tanh(beta d) = +-(1 - 2 eps) needs
  // |d| < 11.6 / beta: the root lies in |ln E| <= bound
  const Real bound = 2 * beta + 26;
  const Real eb = e_beta, e2b = eb * eb;
  Real El = Real(5.1090890280633251e-12) / e2b, Eh = 1 / El;  // e^-bound
  // start from the root of the grid-aligned plane (1-D THINC's, closed form:
  // E = e^beta (1 - e^{2 beta (q - 1)}) / (e^{2 beta q} - 1)): about 3 steps
  // from there (a step of steepness beta nD along D alone starts farther: the
  // tails are the cell's corners). One expm1 for both factors: the one near 0
  // from its own expm1, the other from it (beyond e^beta: no cancellation)
  Real up, down;  // e^{2 beta q} - 1 and 1 - e^{2 beta (q - 1)}
  if (q < Real(0.5)) {
    up = Kokkos::expm1(2 * beta * q), down = 1 - (1 + up) / e2b;
  } else {
    down = -Kokkos::expm1(2 * beta * (q - 1)), up = (1 - down) * e2b - 1;
  }
  Real E = eb * down / up;
  E = E < El ? El : (E > Eh ? Eh : E);
  for (int it = 0; it < 100; ++it) {
    // P - 1 of both products, so that a cell that is all but full loses no digits
    const Real ma = prod_one_plus_minus_one(al, E), mg = prod_one_plus_minus_one(ga, E);
    const Real F = ma - R * mg + omR;
    // Newton on f = ln[P_al / (R P_ga)] = ln(1 + z), nearly linear in ln E
    // (Newton on F itself, a quartic, crawls in the tails); near the root f
    // by its series, so the last steps take no log
    const Real z = F / (R * (1 + mg));
    const Real f = Kokkos::fabs(z) < Real(1e-4) ? z * (1 - z * (Real(0.5) - z * (Real(1) / 3 - z / 4)))
                                                : Kokkos::log1p(z);
    // f's tolerance: the cell mean to 1e-14
    if (Kokkos::fabs(f) < 8 * beta * nD * Real(1e-14)) break;
    if (f > 0)
      El = E;
    else
      Eh = E;
    // df / d ln E = E sum (al - ga) / ((1 + al E)(1 + ga E)) < 0, without cancellation
    Real sd = 0;
    for (int k = 0; k < 4; ++k) sd += (al[k] - ga[k]) / ((1 + al[k] * E) * (1 + ga[k] * E));
    // the step in ln E; E times exp(s) by exp's (2, 2) Pade approximant when
    // the step is short (exact to O(s^5): the convergence stays quadratic)
    const Real s = sd < 0 ? -f / (E * sd) : bound;
    const Real s2 = s * s / 12;
    Real next = Kokkos::fabs(s) < 1 ? E * (1 + s / 2 + s2) / (1 - s / 2 + s2) : E * Kokkos::exp(s);
    const bool newton = next > El && next < Eh;
    if (!newton) next = Kokkos::sqrt(El * Eh);  // Newton left the bracket: bisect ln E
    E = next;
    // a Newton step this small leaves an error in ln E of about 1e-14
    if ((newton && Kokkos::fabs(s) < Real(1e-7)) || Eh < El * (1 + Real(1e-14))) break;
  }
  x.E = E;
  return p;
}
KOKKOS_INLINE_FUNCTION MthincPlane mthinc_fit(Real q, const Real g[3], Real beta, MthincExps& x) {
  return mthinc_fit(q, g, beta, Kokkos::exp(beta), x);
}
KOKKOS_INLINE_FUNCTION MthincPlane mthinc_fit(Real q, const Real g[3], Real beta) {
  MthincExps x;
  return mthinc_fit(q, g, beta, x);
}

// The plane's offset d (H = (1 + tanh(beta (n . X + d))) / 2) from its E
KOKKOS_INLINE_FUNCTION Real mthinc_offset(const MthincExps& x, Real beta) {
  return -Kokkos::log(x.E) / (2 * beta);
}

// Flux value at a face of a cell along axis `ax`: H's mean over the slab of
// width nu next to the face (`high`: the +1/2 face), from the plane and its
// exps. A cell without an interface gives its own value q.
KOKKOS_INLINE_FUNCTION Real mthinc_face_value(const MthincPlane& p, const MthincExps& x, Real q, Real beta,
                                              int ax, bool high, Real nu) {
  if (p.dom < 0) return q;
  nu = nu < 1 ? nu : Real(1);
  const int D = p.dom, side = mthinc_side(q);
  const bool flip = p.n[D] < 0;
  const Real nD = flip ? -p.n[D] : p.n[D];
  Real k[4];
  if (ax == D) {  // the full cell across D; along it the slab touches X_D = 1/2 or -1/2 (after the flip)
    mthinc_nodes(x.E, x.e1, x.e2, k);
    if (high != flip) {
      const Real a = Real(0.5) - nu;
      return mthinc_mean_along(k, beta, nD, a, Real(0.5), Kokkos::exp(-2 * beta * nD * a), x.eD, side);
    }
    const Real b = Real(-0.5) + nu;
    return mthinc_mean_along(k, beta, nD, Real(-0.5), b, 1 / x.eD, Kokkos::exp(-2 * beta * nD * b), side);
  }
  // the slab across D: its centre at +-(1 - nu)/2 and its width nu along ax
  const Real nt = p.n[ax];
  const Real c = x.E * Kokkos::exp(-beta * nt * (high ? 1 - nu : nu - 1));
  const Real es = Kokkos::exp(-beta * nt * nu * mthinc_gauss);
  if (ax == (D + 1) % 3)
    mthinc_nodes(c, es, x.e2, k);
  else
    mthinc_nodes(c, x.e1, es, k);
  return mthinc_mean_along(k, beta, nD, Real(-0.5), Real(0.5), 1 / x.eD, x.eD, side);
}

}  // namespace softflow
