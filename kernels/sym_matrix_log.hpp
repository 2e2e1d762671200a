// Logarithm and exponential of a symmetric 3x3 matrix in the six-component
// storage of B (0 xx, 1 xy, 2 xz, 3 yy, 4 yz, 5 zz), through its eigenvalues
// (cyclic Jacobi rotations). Used to average positive-definite matrices in
// the log-Euclidean sense (Arsigny et al., SIAM J. Matrix Anal. Appl. 29,
// 2007): exp(sum w log B) is positive definite, and its det is the weighted
// geometric mean of the dets, so averaging det-1 matrices gives det 1 (a
// plain average of them has det >= 1, Minkowski's inequality).
#pragma once
#include "solid_state.hpp"

namespace softflow {

// A = V diag(lam) V^T; V's columns are the eigenvectors
struct SymEigen {
  Real lam[3];
  Real V[3][3];
};

KOKKOS_INLINE_FUNCTION SymEigen sym_eigen(const Real b[6]) {
  Real a[3][3];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) a[r][c] = b[sym_index(r, c)];
  SymEigen e;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) e.V[r][c] = r == c ? Real(1) : Real(0);
  // cyclic Jacobi: each sweep zeroes the three off-diagonal pairs in turn;
  // convergence is quadratic, 6 sweeps reach round-off for any 3x3
  for (int sweep = 0; sweep < 8; ++sweep) {
    const Real off = Kokkos::fabs(a[0][1]) + Kokkos::fabs(a[0][2]) + Kokkos::fabs(a[1][2]);
    const Real scale = Kokkos::fabs(a[0][0]) + Kokkos::fabs(a[1][1]) + Kokkos::fabs(a[2][2]);
    if (!(off > Real(1e-18) * scale)) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (a[p][q] == 0) continue;
        const Real theta = (a[q][q] - a[p][p]) / (2 * a[p][q]);
        const Real t =
            (theta >= 0 ? Real(1) : Real(-1)) / (Kokkos::fabs(theta) + Kokkos::sqrt(theta * theta + 1));
        const Real c = 1 / Kokkos::sqrt(t * t + 1), s = t * c;
        // A <- J^T A J with the rotation J in the (p, q) plane
        for (int k = 0; k < 3; ++k) {
          const Real akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < 3; ++k) {
          const Real apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < 3; ++k) {
          const Real vkp = e.V[k][p], vkq = e.V[k][q];
          e.V[k][p] = c * vkp - s * vkq;
          e.V[k][q] = s * vkp + c * vkq;
        }
      }
  }
  for (int r = 0; r < 3; ++r) e.lam[r] = a[r][r];
  return e;
}

// out = V diag(f) V^T
KOKKOS_INLINE_FUNCTION void sym_compose(const SymEigen& e, const Real f[3], Real out[6]) {
  for (int r = 0; r < 3; ++r)
    for (int c = r; c < 3; ++c) {
      Real s = 0;
      for (int k = 0; k < 3; ++k) s += e.V[r][k] * f[k] * e.V[c][k];
      out[sym_index(r, c)] = s;
    }
}

// log of b into out if b is positive definite; false (out untouched) if not
KOKKOS_INLINE_FUNCTION bool sym_log_positive(const Real b[6], Real out[6]) {
  const SymEigen e = sym_eigen(b);
  if (!(e.lam[0] > 0 && e.lam[1] > 0 && e.lam[2] > 0)) return false;
  const Real f[3] = {Kokkos::log(e.lam[0]), Kokkos::log(e.lam[1]), Kokkos::log(e.lam[2])};
  sym_compose(e, f, out);
  return true;
}

// log of a positive-definite matrix
KOKKOS_INLINE_FUNCTION void sym_log(const Real b[6], Real out[6]) { sym_log_positive(b, out); }

KOKKOS_INLINE_FUNCTION void sym_exp(const Real b[6], Real out[6]) {
  const SymEigen e = sym_eigen(b);
  const Real f[3] = {Kokkos::exp(e.lam[0]), Kokkos::exp(e.lam[1]), Kokkos::exp(e.lam[2])};
  sym_compose(e, f, out);
}

}  // namespace softflow
