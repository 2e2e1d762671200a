// A posteriori positivity of B: where a stage's high-order update leaves B
// inadmissible, that cell's B is recomputed by a first-order update that
// keeps it positive definite (MOOD: Clain, Diot & Loubere, JCP 230, 2011).
//
// Why: B's six components get WENO5 face values one by one, and nothing makes
// the resulting update a positive-definite matrix where B jumps between two
// particles in a collision or across a sheet one to two cells thick. Without
// this, the dense Phi = 0.11, Ca = 0.2 case had det B < 0 from strain 51.8
// and the Ca = 2 case from strain ~5 (results/stationarity.md).
//
// 1. Detection (in solid_rk3_update): the stage's new B of a cell with
//    phi >= phi_min is admissible when it is positive definite
//    (Sylvester: leading minors > 0) and, when every stage starts from
//    det B = 1 (unimodular projection on), det B is within det_tol of 1.
//    A troubled cell keeps its stage-start B and is flagged. phi_min is
//    phi_solid with the B extension (below it the extension rebuilds B from
//    the solid cells after every stage, so the stage's own B there is never
//    used), else phi_fluid_cut.
// 2. Fallback (b_upwind_fallback): from the stage-start B, over the stage's
//    time tau = gdt + zdt,
//    - upwind advection: B_a = the mean of B (weight 1 - c) and of the
//      inflow neighbours' B_nb (weights tau |u_f| / dx), c = tau sum_in
//      |u_f| / dx (the advective form of donor-cell upwinding; the MAC
//      velocity is divergence-free; for c > 1, the inflow neighbours' mean).
//      The mean is log-Euclidean, exp(sum w log B) (kernels/sym_matrix_log.hpp):
//      positive definite, and det-1 matrices average to det 1, so the
//      fallback adds no volume error (a plain mean of different det-1
//      matrices has det > 1: it reached 1.035 in the dense Ca = 0.2 case
//      and 1.12 at Ca = 2);
//    - stretch as a congruence: B_new = F B_a F^T with F = I + tau L, positive
//      definite for any invertible F. It differs from the explicit source
//      B_a + tau (L B_a + B_a L^T) by tau^2 L B_a L^T: first order.
//    The cell's right-hand side (which the next RK3 stage reads as its
//    "before") becomes the effective rate (B_new - B_start) / tau.
// The stage-start B of a neighbour is its current B where the update did not
// write it (troubled cells, cells outside the update's region, ghosts), and
// B - gdt r_now - zdt r_before (exact up to round-off) where it did.
#pragma once
#include "flow_state.hpp"
#include "solid_state.hpp"
#include "sym_matrix_log.hpp"
#include "velocity_gradient.hpp"

namespace softflow {

// what the update did to a cell's B (the flag array)
constexpr Real b_updated = 0, b_troubled = 1, b_reset = 2;

// The detector's settings. det_tol <= 0: positive definiteness only.
struct BCheck {
  bool on = false;
  Real det_tol = 0;
  Real phi_min = 0;  // cells with a smaller new phi are not checked
  Field3 flag;       // b_updated / b_troubled / b_reset per cell of the update's region
};

KOKKOS_INLINE_FUNCTION bool b_admissible(const Real b[6], Real det_tol) {
  const Real d = det_sym(b[0], b[1], b[2], b[3], b[4], b[5]);
  if (!(b[0] > 0 && b[0] * b[3] - b[1] * b[1] > 0 && d > 0)) return false;
  return det_tol <= 0 || Kokkos::fabs(d - 1) <= det_tol;
}

// B_new = F B F^T with F = I + tau L (the six components in place)
KOKKOS_INLINE_FUNCTION void stretch_congruence(const Gradient3& g, Real tau, Real b[6]) {
  Real F[3][3], FB[3][3];
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) F[a][c] = (a == c ? Real(1) : Real(0)) + tau * g.L[a][c];
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) {
      Real s = 0;
      for (int e = 0; e < 3; ++e) s += F[a][e] * b[sym_index(e, c)];
      FB[a][c] = s;
    }
  Real out[6];
  for (int a = 0; a < 3; ++a)
    for (int c = a; c < 3; ++c) {
      Real s = 0;
      for (int e = 0; e < 3; ++e) s += FB[a][e] * F[c][e];
      out[sym_index(a, c)] = s;
    }
  for (int m = 0; m < 6; ++m) b[m] = out[m];
}

// The troubled cells of `region` (check.flag == b_troubled): their fallback
// B into `now` (temporarily), then swapped in (two passes: the first reads
// the neighbours' stage-start B, which the second overwrites).
inline void b_upwind_fallback(const Grid& g, const FlowState& flow, const SolidFields& f,
                              const SolidFields& now, const SolidFields& before, const BCheck& check,
                              Real gdt, Real zdt, const Range3& region) {
  const SolidViews q(f), a(now), b(before);
  const Field3 flag = check.flag;
  auto u = flow.u, v = flow.v, w = flow.w;
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz, tau = gdt + zdt;
  const Range3 r = region;
  par_for(
      "solid_b_fallback", region, KOKKOS_LAMBDA(int i, int j, int k) {
        if (flag(i, j, k) != b_troubled) return;
        // the stage-start B of a cell
        auto start = [&](int m, int ii, int jj, int kk) {
          const Real x = q.B(m, ii, jj, kk);
          if (!r.contains(ii, jj, kk) || flag(ii, jj, kk) != b_updated) return x;
          return x - (gdt * a.B(m, ii, jj, kk) + zdt * b.B(m, ii, jj, kk));
        };
        // inflow faces: the neighbour and |u_f| / dx
        int nb[6][3];
        Real rate[6];
        int n = 0;
        auto inflow = [&](Real vel_in, int di, int dj, int dk, Real id) {
          if (vel_in > 0) {
            nb[n][0] = i + di, nb[n][1] = j + dj, nb[n][2] = k + dk;
            rate[n++] = vel_in * id;
          }
        };
        inflow(u(i - 1, j, k), -1, 0, 0, idx);
        inflow(-u(i, j, k), 1, 0, 0, idx);
        inflow(v(i, j - 1, k), 0, -1, 0, idy);
        inflow(-v(i, j, k), 0, 1, 0, idy);
        inflow(w(i, j, k - 1), 0, 0, -1, idz);
        inflow(-w(i, j, k), 0, 0, 1, idz);
        Real c = 0;
        for (int e = 0; e < n; ++e) c += tau * rate[e];
        // weights of the cell itself and of each inflow neighbour
        const Real self = c <= 1 ? 1 - c : Real(0), scale = c <= 1 ? tau : tau / c;
        // the weighted mean of the cell's and its inflow neighbours' B, in
        // the log-Euclidean sense (a plain mean where one is not positive
        // definite, which the stage start should never hold)
        Real bn[6] = {0, 0, 0, 0, 0, 0}, lin[6] = {0, 0, 0, 0, 0, 0};
        bool spd = true;
        for (int e = -1; e < n; ++e) {
          const Real wgt = e < 0 ? self : scale * rate[e];
          if (wgt == 0) continue;
          Real be[6];
          for (int m = 0; m < 6; ++m)
            be[m] = e < 0 ? start(m, i, j, k) : start(m, nb[e][0], nb[e][1], nb[e][2]);
          for (int m = 0; m < 6; ++m) lin[m] += wgt * be[m];
          Real lg[6];
          spd = spd && sym_log_positive(be, lg);
          if (!spd) continue;
          for (int m = 0; m < 6; ++m) bn[m] += wgt * lg[m];
        }
        if (spd) {
          const Real lg[6] = {bn[0], bn[1], bn[2], bn[3], bn[4], bn[5]};
          sym_exp(lg, bn);
        } else {
          for (int m = 0; m < 6; ++m) bn[m] = lin[m];
        }
        stretch_congruence(velocity_gradient(u, v, w, i, j, k, idx, idy, idz), tau, bn);
        for (int m = 0; m < 6; ++m) a.field(1 + m)(i, j, k) = bn[m];
      });
  par_for(
      "solid_b_fallback_swap", region, KOKKOS_LAMBDA(int i, int j, int k) {
        if (flag(i, j, k) != b_troubled) return;
        for (int m = 0; m < 6; ++m) {
          const Real old = q.B(m, i, j, k), bn = a.B(m, i, j, k);
          q.field(1 + m)(i, j, k) = bn;
          a.field(1 + m)(i, j, k) = (bn - old) / tau;
        }
      });
}

// the number of troubled cells of `region`
inline long count_troubled(const BCheck& check, const Range3& region) {
  const Field3 flag = check.flag;
  long n = 0;
  par_reduce(
      "solid_b_troubled_count", region,
      KOKKOS_LAMBDA(int i, int j, int k, long& acc) { acc += flag(i, j, k) == b_troubled ? 1 : 0; },
      Kokkos::Sum<long>(n));
  return n;
}

}  // namespace softflow
