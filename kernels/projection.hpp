// The two point-wise halves of the pressure projection around the Poisson
// solve: the divergence of the provisional velocity as the right-hand side,
// and the correction u = u* - alpha dt grad(phi).
#pragma once
#include "../src/poisson.hpp"
#include "flow_state.hpp"

namespace softflow {

KOKKOS_INLINE_FUNCTION Real divergence(const Field3& u, const Field3& v, const Field3& w, int i, int j, int k,
                                       Real idx, Real idy, Real idz) {
  return (u(i, j, k) - u(i - 1, j, k)) * idx + (v(i, j, k) - v(i, j - 1, k)) * idy +
         (w(i, j, k) - w(i, j, k - 1)) * idz;
}

// rhs(j, i, k) = div u / (alpha dt), in the Poisson solver's y-pencil order
inline void divergence_to_poisson(const Grid& g, const FlowState& s, Real adt, const Array1& rhs) {
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz, inv = 1 / adt;
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl;
  auto u = s.u, v = s.v, w = s.w;
  par_for(
      "projection_divergence", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        rhs(PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl)) =
            divergence(u, v, w, i, j, k, idx, idy, idz) * inv;
      });
}

inline void poisson_to_field(const Grid& g, const Array1& sol, const Field3& p) {
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl;
  par_for(
      "projection_copy_pressure", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        p(i, j, k) = sol(PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl));
      });
}

// u -= alpha dt grad(phi) on the interior unknowns (phi's ghosts must be set)
inline void correct_velocity(const Grid& g, const FlowState& s, const Field3& p, Real adt) {
  const Real cx = adt / g.dx, cy = adt / g.dy, cz = adt / g.dz;
  const int vtop = Grid::ng + g.ny - 1;
  auto u = s.u, v = s.v, w = s.w;
  par_for(
      "projection_correct", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const Real pc = p(i, j, k);
        u(i, j, k) -= cx * (p(i + 1, j, k) - pc);
        w(i, j, k) -= cz * (p(i, j, k + 1) - pc);
        if (j < vtop) v(i, j, k) -= cy * (p(i, j + 1, k) - pc);
      });
}

}  // namespace softflow
