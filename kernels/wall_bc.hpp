// Ghost values in y from the walls at y = -h (moving at -V_w) and y = +h
// (moving at +V_w), no slip and no penetration.
//  - u, w live at cell centres in y: odd reflection about the wall value, so
//    the average of the first cell and its ghost is the wall velocity.
//  - v lives on y-faces: the wall faces hold 0, ghosts are odd reflections.
//  - p: homogeneous Neumann (even reflection).
// Runs over the whole x-z storage plane, after the halo exchange.
#pragma once
#include "flow_state.hpp"

namespace softflow {

inline void apply_velocity_walls(const Grid& g, const FlowState& s, Real wall_velocity) {
  const int ng = Grid::ng, ny = g.ny;
  auto u = s.u, v = s.v, w = s.w;
  const Real ub = -wall_velocity, ut = wall_velocity;
  par_for(
      "walls_velocity", Range3{0, g.sx(), 0, ng, 0, g.sz()}, KOKKOS_LAMBDA(int i, int m, int k) {
        const int jb = ng - 1 - m, jt = ng + ny + m;  // ghost rows below and above
        u(i, jb, k) = 2 * ub - u(i, ng + m, k);
        u(i, jt, k) = 2 * ut - u(i, ng + ny - 1 - m, k);
        w(i, jb, k) = -w(i, ng + m, k);
        w(i, jt, k) = -w(i, ng + ny - 1 - m, k);
        // v: the wall faces are ng-1 and ng+ny-1; ng ghost rows lie beyond each
        v(i, ng + ny + m, k) = -v(i, ng + ny - 2 - m, k);
        if (m == 0) {
          v(i, ng - 1, k) = 0;
          v(i, ng + ny - 1, k) = 0;
        } else {
          v(i, ng - 1 - m, k) = -v(i, ng - 1 + m, k);
        }
      });
}

inline void apply_pressure_walls(const Grid& g, const Field3& p) {
  const int ng = Grid::ng, ny = g.ny;
  par_for(
      "walls_pressure", Range3{0, g.sx(), 0, ng, 0, g.sz()}, KOKKOS_LAMBDA(int i, int m, int k) {
        p(i, ng - 1 - m, k) = p(i, ng + m, k);
        p(i, ng + ny + m, k) = p(i, ng + ny - 1 - m, k);
      });
}

}  // namespace softflow
