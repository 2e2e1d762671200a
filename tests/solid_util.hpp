// Helpers for the solid-phase tests: prescribed velocity fields and a
// transport-only RK3 step.
#pragma once
#include "../kernels/rk3_update.hpp"
#include "../kernels/solid_state.hpp"
#include "test_util.hpp"

namespace softflow::test {

// The det-1 stretch R(theta) diag(l, 1 / l, 1) R(theta)^T, R about z, in
// B's six-component storage (0 xx, 1 xy, 2 xz, 3 yy, 4 yz, 5 zz)
KOKKOS_INLINE_FUNCTION void stretch_about_z(double l, double theta, double b[6]) {
  const double c = Kokkos::cos(theta), s = Kokkos::sin(theta);
  b[0] = l * c * c + s * s / l;
  b[1] = (l - 1 / l) * c * s;
  b[2] = 0;
  b[3] = l * s * s + c * c / l;
  b[4] = 0;
  b[5] = 1;
}

// det of a B in six-component storage
KOKKOS_INLINE_FUNCTION double det6(const double b[6]) { return det_sym(b[0], b[1], b[2], b[3], b[4], b[5]); }

// Sets u, v, w on every storage face (ghosts included) from f(x, y, z, t) -> {u, v, w}.
template <class F>
void set_velocity(FlowSolver& s, const F& f, double t) {
  const Grid g = s.grid();
  auto u = s.state().u, v = s.state().v, w = s.state().w;
  par_for(
      "test_set_velocity", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        u(i, j, k) = f(g.xf(i), g.yc(j), g.zc(k), t).u;
        v(i, j, k) = f(g.xc(i), g.yf(j), g.zc(k), t).v;
        w(i, j, k) = f(g.xc(i), g.yc(j), g.zf(k), t).w;
      });
}

// v = 0 on the two walls, as in the solver: a prescribed flow that crossed
// them would carry phi's far tails (~1e-9) out of the box
inline void impermeable_walls(FlowSolver& s) {
  const Grid g = s.grid();
  auto v = s.state().v;
  const int wall_lo = Grid::ng - 1, wall_hi = Grid::ng + g.ny - 1;
  par_for(
      "test_impermeable_walls", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        if (j == wall_lo || j == wall_hi) v(i, j, k) = 0;
      });
}

struct Vec3 {
  double u, v, w;
};

// The velocity of steady tank-treading: streamlines x'^2/a^2 + y'^2/b^2 =
// const in axes turned by theta (cos c, sin n) about (xc, y = 0), turning at
// rate w; divergence-free, tangent to the ellipse of axes a, b.
struct TankTreading {
  double w, a, b, c, n, xc;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double x, double y, double, double) const {
    const double X = c * (x - xc) + n * y, Y = -n * (x - xc) + c * y;
    const double U = -w * a / b * Y, V = w * b / a * X;
    return {c * U - n * V, n * U + c * V, 0.0};
  }
};

// One RK3 step of phi and B alone, in the velocity f prescribes at each
// stage's start (walls impermeable).
template <class F>
void transport_step(FlowSolver& s, const F& f, double dt) {
  s.solid()->begin_step();
  for (int st = 0; st < Rk3::stages; ++st) {
    set_velocity(s, f, s.time + Rk3::c[st] * dt);
    impermeable_walls(s);
    s.solid()->advance_stage(s.state(), Rk3::gamma[st] * dt, Rk3::zeta[st] * dt, st == Rk3::stages - 1);
    s.solid()->end_stage();
  }
  s.time += dt;
  ++s.step;
}

// Particle keys for a case with walls at rest (G given directly)
inline std::vector<std::string> solid_keys(std::vector<std::string> extra = {}) {
  std::vector<std::string> o = {"particles.radius=0.3", "particles.count=1", "particles.placement=centre",
                                "particles.shear_modulus=1.0"};
  o.insert(o.end(), extra.begin(), extra.end());
  return o;
}

// max |a(i,j,k) - f(i,j,k)| over the interior
template <class F>
double max_error(const Grid& g, const Field3& a, const F& f) {
  double m = 0;
  par_reduce(
      "test_max_error", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& x) {
        x = Kokkos::fmax(x, Kokkos::fabs(a(i, j, k) - f(i, j, k)));
      },
      Kokkos::Max<double>(m));
  return global_max(m);
}

// Interface cells (0.01 < phi < 0.99) over the interior, summed over the ranks
inline double interface_cells(const Grid& g, const Field3& phi) {
  double n = 0;
  par_reduce(
      "test_interface_cells", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) {
        const double p = phi(i, j, k);
        a += (p > 0.01 && p < 0.99) ? 1.0 : 0.0;
      },
      Kokkos::Sum<double>(n));
  return global_sum(n);
}

}  // namespace softflow::test
