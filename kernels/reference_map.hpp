// Point-wise numerics of the reference map (Kamrin, Rycroft & Nave, JMPS
// 2012; Rycroft et al., JFM 2020): each cell holds xi, the position its
// material had in the undeformed particle. The deformation gradient is
// F = (grad xi)^-1, so B = F F^T, and the particle is the set of points
// whose xi lies in the reference sphere |xi - c| < r. Shape and stretch come
// from one field, so solid cannot leave the particle without being
// stretched. Unit-tested on the host (tests/test_reference_map.cpp).
#pragma once
#include "../src/types.hpp"

namespace softflow {

// J[a][b] = d xi_a / d x_b; F = J^-1 by the adjugate. Returns det J (F is
// left alone where det J is not positive: a broken map)
KOKKOS_INLINE_FUNCTION Real invert_map_gradient(const Real J[3][3], Real F[3][3]) {
  const Real c00 = J[1][1] * J[2][2] - J[1][2] * J[2][1];
  const Real c01 = J[1][2] * J[2][0] - J[1][0] * J[2][2];
  const Real c02 = J[1][0] * J[2][1] - J[1][1] * J[2][0];
  const Real det = J[0][0] * c00 + J[0][1] * c01 + J[0][2] * c02;
  if (!(det > 0)) return det;
  const Real id = 1 / det;
  F[0][0] = c00 * id;
  F[1][0] = c01 * id;
  F[2][0] = c02 * id;
  F[0][1] = (J[0][2] * J[2][1] - J[0][1] * J[2][2]) * id;
  F[1][1] = (J[0][0] * J[2][2] - J[0][2] * J[2][0]) * id;
  F[2][1] = (J[0][1] * J[2][0] - J[0][0] * J[2][1]) * id;
  F[0][2] = (J[0][1] * J[1][2] - J[0][2] * J[1][1]) * id;
  F[1][2] = (J[0][2] * J[1][0] - J[0][0] * J[1][2]) * id;
  F[2][2] = (J[0][0] * J[1][1] - J[0][1] * J[1][0]) * id;
  return det;
}

// B = F F^T with F = J^-1, six components (xx, xy, xz, yy, yz, zz); I where
// the map is broken (det J <= 0), so no stress; the det B diagnostics do not
// see such a cell, series.csv's map_det_corrected does (as infinite)
KOKKOS_INLINE_FUNCTION void b_from_map_gradient(const Real J[3][3], Real B[6]) {
  Real F[3][3];
  if (!(invert_map_gradient(J, F) > 0)) {
    B[0] = B[3] = B[5] = 1;
    B[1] = B[2] = B[4] = 0;
    return;
  }
  const int a_of[6] = {0, 0, 0, 1, 1, 2}, b_of[6] = {0, 1, 2, 1, 2, 2};
  for (int m = 0; m < 6; ++m) {
    const int a = a_of[m], b = b_of[m];
    B[m] = F[a][0] * F[b][0] + F[a][1] * F[b][1] + F[a][2] * F[b][2];
  }
}

// The share of a cell (sides h[3]) inside the reference sphere |xi - c| < r,
// with xi linear across the cell: xi(x0 + s) = xi0 + J s. ns^3 sub-cells;
// each counts its depth inside the sphere, measured along xi's gradient
// and converted to physical length, as a linear ramp one sub-cell wide
// (a plane's exact share of a sub-cell cut parallel to a face). The ramp
// makes the share continuous in r and in xi. d = xi0 - c.
KOKKOS_INLINE_FUNCTION Real reference_ball_share(const Real d[3], const Real J[3][3], Real r, const Real h[3],
                                                 int ns) {
  Real in = 0;
  const Real hs = (h[0] + h[1] + h[2]) / (3 * ns);  // a sub-cell's side
  for (int a = 0; a < ns; ++a)
    for (int b = 0; b < ns; ++b)
      for (int e = 0; e < ns; ++e) {
        const Real s[3] = {h[0] * ((a + Real(0.5)) / ns - Real(0.5)),
                           h[1] * ((b + Real(0.5)) / ns - Real(0.5)),
                           h[2] * ((e + Real(0.5)) / ns - Real(0.5))};
        Real q[3];
        for (int m = 0; m < 3; ++m) q[m] = d[m] + J[m][0] * s[0] + J[m][1] * s[1] + J[m][2] * s[2];
        const Real rho = Kokkos::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
        // |grad_x |xi - c|| = |J^T q| / rho: xi-space depth to physical length
        Real g2 = 0;
        for (int m = 0; m < 3; ++m) {
          const Real gm = J[0][m] * q[0] + J[1][m] * q[1] + J[2][m] * q[2];
          g2 += gm * gm;
        }
        const Real slope = rho > 0 ? Kokkos::sqrt(g2) / rho : Real(1);
        const Real depth = slope > 0 ? (r - rho) / slope : (r - rho);
        const Real f = Real(0.5) + depth / hs;
        in += f < 0 ? Real(0) : (f > 1 ? Real(1) : f);
      }
  return in / (ns * ns * ns);
}

// The band's soft edge: the share of its own (advected) value that a cell
// outside the inside set keeps when the band is refitted. 1 where that value
// maps into the reference sphere, 0 where it maps farther than width beyond
// it, linear between (q = xi - c). A cell leaving the inside set then
// hands its value over to the fit gradually instead of in one refit, which
// made its neighbours' central-difference det jump by up to 12% (round 36).
KOKKOS_INLINE_FUNCTION Real soft_edge_weight(const Real q[3], Real r, Real width) {
  const Real rho = Kokkos::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2]);
  const Real w = (r + width - rho) / width;
  return w < 0 ? Real(0) : (w > 1 ? Real(1) : w);
}

// A prior gradient for the fits below, G[m][b] = d xi_m / d o_b
struct GradientPrior {
  Real G[3][3];
};

// Affine least-squares fit xi(x) ~ a + G (x - x0) through sample points
// (offsets o from x0, values v, weights w), accumulated one point at a time.
// solve() gives a (the value at x0) and, if asked, G (G[m][b] = d xi_m /
// d x_b); false where the points do not span 3-D.
struct AffineFit {
  Real M[4][4] = {};  // sum w p p^T, p = (1, o)
  Real R[4][3] = {};  // sum w p v^T
  KOKKOS_INLINE_FUNCTION void add(const Real o[3], const Real v[3], Real w) {
    const Real p[4] = {1, o[0], o[1], o[2]};
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) M[a][b] += w * p[a] * p[b];
      for (int m = 0; m < 3; ++m) R[a][m] += w * p[a] * v[m];
    }
  }
  // ridge toward a prior gradient G0 (G0[m][b] = d xi_m / d o_b, in the
  // offsets' units) with weight lambda: the fit stays well posed where the
  // points span fewer than three directions (a tip one cell thin), and
  // follows G0 in the directions they do not span
  KOKKOS_INLINE_FUNCTION void prior(const Real G0[3][3], Real lambda) {
    for (int b = 0; b < 3; ++b) {
      M[1 + b][1 + b] += lambda;
      for (int m = 0; m < 3; ++m) R[1 + b][m] += lambda * G0[m][b];
    }
  }
  // Gaussian elimination with partial pivoting on the 4x4 normal equations;
  // a pivot below tol times the largest diagonal entry means the points are
  // (nearly) coplanar
  KOKKOS_INLINE_FUNCTION bool solve(Real out[3], Real G[3][3] = nullptr, Real tol = 1e-6) const {
    Real A[4][7];
    Real dmax = 0;
    for (int a = 0; a < 4; ++a) {
      for (int b = 0; b < 4; ++b) A[a][b] = M[a][b];
      for (int m = 0; m < 3; ++m) A[a][4 + m] = R[a][m];
      dmax = M[a][a] > dmax ? M[a][a] : dmax;
    }
    for (int c = 0; c < 4; ++c) {
      int p = c;
      for (int a = c + 1; a < 4; ++a)
        if (Kokkos::fabs(A[a][c]) > Kokkos::fabs(A[p][c])) p = a;
      if (!(Kokkos::fabs(A[p][c]) > tol * dmax)) return false;
      if (p != c)
        for (int b = 0; b < 7; ++b) {
          const Real t = A[c][b];
          A[c][b] = A[p][b];
          A[p][b] = t;
        }
      for (int a = c + 1; a < 4; ++a) {
        const Real f = A[a][c] / A[c][c];
        for (int b = c; b < 7; ++b) A[a][b] -= f * A[c][b];
      }
    }
    Real x[4][3];
    for (int c = 3; c >= 0; --c)
      for (int m = 0; m < 3; ++m) {
        Real s = A[c][4 + m];
        for (int b = c + 1; b < 4; ++b) s -= A[c][b] * x[b][m];
        x[c][m] = s / A[c][c];
      }
    for (int m = 0; m < 3; ++m) out[m] = x[0][m];
    if (G)
      for (int m = 0; m < 3; ++m)
        for (int b = 0; b < 3; ++b) G[m][b] = x[1 + b][m];
    return true;
  }
};

}  // namespace softflow
