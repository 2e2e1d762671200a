// Pressure Poisson solver: periodic in x and z, homogeneous Neumann at the
// walls, for the 7-point Laplacian of the MAC grid. FFT in x and z turns it
// into one tridiagonal system in y per wavenumber pair, with the discrete
// operator's eigenvalues (2 cos(2 pi k / n) - 2) / d^2, so the projected
// velocity is divergence-free to round-off.
//
// The same machinery solves the Helmholtz problems of the implicit viscous
// step, (I - beta L) u = r, for each velocity component with its own wall rows
// (LineOperator below).
//
// Set-up (constructor): work arrays, FFT plans, eigenvalues. Apply (solve):
// transposes, FFTs and the tridiagonal sweeps, allocation-free.
#pragma once
#include "fft.hpp"
#include "transpose.hpp"

namespace softflow {

// How the first and last rows in y close the 7-point Laplacian:
//  - neumann: cell-centred unknown, zero normal gradient (pressure);
//  - dirichlet_centre: cell-centred unknown with its wall value carried by the
//    right-hand side (u and w: ghost = 2 u_wall - u_first, diagonal -3 / dy^2);
//  - dirichlet_face: face unknowns between the walls (v: ny - 1 of them; the
//    wall faces hold 0, and the last row, the top wall's face, returns 0).
enum class WallRows { neumann, dirichlet_centre, dirichlet_face };

// The operator (identity I + laplacian L) solved per line.
struct LineOperator {
  Real identity = 0;
  Real laplacian = 1;
  WallRows walls = WallRows::neumann;
};

class PoissonSolver {
 public:
  PoissonSolver(const Decomposition& dec, const Grid& g);

  // The right-hand side in y-pencil order, index j + ny * (i + nxl * k) with
  // interior indices (no ghosts). solve() overwrites it with the solution.
  Array1 rhs() const { return y_; }
  KOKKOS_INLINE_FUNCTION static long index(int i, int j, int k, int ny, int nxl) {
    return j + long(ny) * (i + long(nxl) * k);
  }

  // Solves L p = rhs. The wavenumber-(0,0) mode is pinned by p = 0 in the
  // first cell of its line, so the rhs must have zero mean (it does for a
  // divergence); the solution's mean is then arbitrary.
  void solve() { solve(y_, LineOperator{}); }
  // Solves (identity + laplacian L) x = y in place, for any array laid out like rhs()
  void solve(const Array1& y, const LineOperator& op);

  Transposer& transposer() { return tr_; }

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void tridiagonal(const Array1& y, const LineOperator& op);

 private:
  const Decomposition& dec_;
  Grid g_;
  Transposer tr_;
  Array1 y_, x_, z_, scratch_;
  Array1 lamx_, lamz_;
  LineFft fft_x_, fft_z_;
};

}  // namespace softflow
