// The low-storage three-stage Runge-Kutta update of Wray / Rai & Moin, as used
// with the Kim-Moin fractional step:
//   u* = u + dt (gamma_s N_s + zeta_s N_{s-1}),  then project with alpha_s dt,
// alpha_s = gamma_s + zeta_s. Stage times: t + c_s dt.
#pragma once
#include "flow_state.hpp"

namespace softflow {

struct Rk3 {
  static constexpr int stages = 3;
  static constexpr Real gamma[3] = {8.0 / 15.0, 5.0 / 12.0, 3.0 / 4.0};
  static constexpr Real zeta[3] = {0.0, -17.0 / 60.0, -5.0 / 12.0};
  static constexpr Real alpha[3] = {8.0 / 15.0, 2.0 / 15.0, 1.0 / 3.0};
  static constexpr Real c[3] = {0.0, 8.0 / 15.0, 2.0 / 3.0};      // stage start times
  static constexpr Real c_end[3] = {8.0 / 15.0, 2.0 / 3.0, 1.0};  // stage end times
};

inline void rk3_update(const Grid& g, const FlowState& s, const MomentumRhs& now, const MomentumRhs& before,
                       Real gdt, Real zdt) {
  auto u = s.u, v = s.v, w = s.w;
  auto nu = now.u, nv = now.v, nw = now.w, bu = before.u, bv = before.v, bw = before.w;
  const int vtop = Grid::ng + g.ny - 1;
  par_for(
      "rk3_update", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        u(i, j, k) += gdt * nu(i, j, k) + zdt * bu(i, j, k);
        w(i, j, k) += gdt * nw(i, j, k) + zdt * bw(i, j, k);
        if (j < vtop) v(i, j, k) += gdt * nv(i, j, k) + zdt * bv(i, j, k);
      });
}

// The same with a Crank-Nicolson force across the stage: + cdt (F_now + F_before),
// cdt = alpha dt / 2 (the hyper-elastic force).
inline void rk3_update_cn(const Grid& g, const FlowState& s, const MomentumRhs& now,
                          const MomentumRhs& before, Real gdt, Real zdt, const MomentumRhs& fnow,
                          const MomentumRhs& fbefore, Real cdt) {
  auto u = s.u, v = s.v, w = s.w;
  auto nu = now.u, nv = now.v, nw = now.w, bu = before.u, bv = before.v, bw = before.w;
  auto fu = fnow.u, fv = fnow.v, fw = fnow.w, eu = fbefore.u, ev = fbefore.v, ew = fbefore.w;
  const int vtop = Grid::ng + g.ny - 1;
  par_for(
      "rk3_update_cn", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        u(i, j, k) += gdt * nu(i, j, k) + zdt * bu(i, j, k) + cdt * (fu(i, j, k) + eu(i, j, k));
        w(i, j, k) += gdt * nw(i, j, k) + zdt * bw(i, j, k) + cdt * (fw(i, j, k) + ew(i, j, k));
        if (j < vtop) v(i, j, k) += gdt * nv(i, j, k) + zdt * bv(i, j, k) + cdt * (fv(i, j, k) + ev(i, j, k));
      });
}

}  // namespace softflow
