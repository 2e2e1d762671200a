// Pressure Poisson solver: periodic in x and z, homogeneous Neumann at the
// walls, for the 7-point Laplacian of the MAC grid. FFT in x and z turns it
// into one tridiagonal system in y per wavenumber pair, with the discrete
// operator's eigenvalues (2 cos(2 pi k / n) - 2) / d^2, so the projected
// velocity is divergence-free to round-off.
//
// Set-up (constructor): work arrays, FFT plans, eigenvalues. Apply (solve):
// transposes, FFTs and the tridiagonal sweeps, allocation-free.
#pragma once
#include "fft.hpp"
#include "transpose.hpp"

namespace softflow {

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
  void solve();

  Transposer& transposer() { return tr_; }

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void tridiagonal();

 private:
  const Decomposition& dec_;
  Grid g_;
  Transposer tr_;
  Array1 y_, x_, z_, scratch_;
  Array1 lamx_, lamz_;
  LineFft fft_x_, fft_z_;
};

}  // namespace softflow
