// The velocity gradient L_ab = d u_a / d x_b at a cell centre of the MAC grid,
// second order: diagonal terms from the cell's own faces, off-diagonal terms
// as central differences of the face velocities averaged to the centres.
#pragma once
#include "flow_state.hpp"
#include "solid_state.hpp"

namespace softflow {

struct Gradient3 {
  Real L[3][3];
};

KOKKOS_INLINE_FUNCTION Gradient3 velocity_gradient(const Field3& u, const Field3& v, const Field3& w, int i,
                                                   int j, int k, Real idx, Real idy, Real idz) {
  Gradient3 g;
  g.L[0][0] = (u(i, j, k) - u(i - 1, j, k)) * idx;
  g.L[1][1] = (v(i, j, k) - v(i, j - 1, k)) * idy;
  g.L[2][2] = (w(i, j, k) - w(i, j, k - 1)) * idz;
  // u at centres (i, j+-1, k) and (i, j, k+-1)
  g.L[0][1] = 0.25 * ((u(i, j + 1, k) + u(i - 1, j + 1, k)) - (u(i, j - 1, k) + u(i - 1, j - 1, k))) * idy;
  g.L[0][2] = 0.25 * ((u(i, j, k + 1) + u(i - 1, j, k + 1)) - (u(i, j, k - 1) + u(i - 1, j, k - 1))) * idz;
  g.L[1][0] = 0.25 * ((v(i + 1, j, k) + v(i + 1, j - 1, k)) - (v(i - 1, j, k) + v(i - 1, j - 1, k))) * idx;
  g.L[1][2] = 0.25 * ((v(i, j, k + 1) + v(i, j - 1, k + 1)) - (v(i, j, k - 1) + v(i, j - 1, k - 1))) * idz;
  g.L[2][0] = 0.25 * ((w(i + 1, j, k) + w(i + 1, j, k - 1)) - (w(i - 1, j, k) + w(i - 1, j, k - 1))) * idx;
  g.L[2][1] = 0.25 * ((w(i, j + 1, k) + w(i, j + 1, k - 1)) - (w(i, j - 1, k) + w(i, j - 1, k - 1))) * idy;
  return g;
}

// Upper-convected source of B: (L B + B L^T)_ab for component m = (a, b)
KOKKOS_INLINE_FUNCTION Real upper_convected_source(const Gradient3& g, const Real B[6], int a, int b) {
  Real s = 0;
  for (int c = 0; c < 3; ++c) s += g.L[a][c] * B[sym_index(c, b)] + B[sym_index(a, c)] * g.L[b][c];
  return s;
}

}  // namespace softflow
