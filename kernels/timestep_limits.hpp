// The advective stability measure max(|u|/dx + |v|/dy + |w|/dz) over the
// local cells, with the face velocities of each cell's +x, +y, +z sides.
#pragma once
#include "flow_state.hpp"

namespace softflow {

inline Real max_advective_rate(const Grid& g, const FlowState& s) {
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  auto u = s.u, v = s.v, w = s.w;
  Real r = 0;
  par_reduce(
      "timestep_advective_rate", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& m) {
        const Real a =
            Kokkos::fabs(u(i, j, k)) * idx + Kokkos::fabs(v(i, j, k)) * idy + Kokkos::fabs(w(i, j, k)) * idz;
        m = a > m ? a : m;
      },
      Kokkos::Max<Real>(r));
  return r;
}

}  // namespace softflow
