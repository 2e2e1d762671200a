// Explicit right-hand side of the momentum equation on the MAC grid:
//   N(u) = -div(u u) + nu lap u (+ manufactured forcing in tests)
// Advection in the conservative, energy-conserving central form of the
// staggered grid (second order); diffusion with the 7-point Laplacian, valid
// for uniform viscosity (div u = 0). Pressure is left to the projection.
#pragma once
#include "flow_state.hpp"
#include "manufactured.hpp"

namespace softflow {

struct AdvectionDiffusion {
  Real idx, idy, idz;

  // div(u u) of x-momentum at face (i+1/2, j, k)
  template <class V>
  KOKKOS_INLINE_FUNCTION Real adv_u(const V& u, const V& v, const V& w, int i, int j, int k) const {
    const Real uuxp = 0.25 * (u(i, j, k) + u(i + 1, j, k)) * (u(i, j, k) + u(i + 1, j, k));
    const Real uuxm = 0.25 * (u(i - 1, j, k) + u(i, j, k)) * (u(i - 1, j, k) + u(i, j, k));
    const Real uvyp = 0.25 * (u(i, j, k) + u(i, j + 1, k)) * (v(i, j, k) + v(i + 1, j, k));
    const Real uvym = 0.25 * (u(i, j - 1, k) + u(i, j, k)) * (v(i, j - 1, k) + v(i + 1, j - 1, k));
    const Real uwzp = 0.25 * (u(i, j, k) + u(i, j, k + 1)) * (w(i, j, k) + w(i + 1, j, k));
    const Real uwzm = 0.25 * (u(i, j, k - 1) + u(i, j, k)) * (w(i, j, k - 1) + w(i + 1, j, k - 1));
    return (uuxp - uuxm) * idx + (uvyp - uvym) * idy + (uwzp - uwzm) * idz;
  }

  // div(u v) of y-momentum at face (i, j+1/2, k)
  template <class V>
  KOKKOS_INLINE_FUNCTION Real adv_v(const V& u, const V& v, const V& w, int i, int j, int k) const {
    const Real uvxp = 0.25 * (u(i, j, k) + u(i, j + 1, k)) * (v(i, j, k) + v(i + 1, j, k));
    const Real uvxm = 0.25 * (u(i - 1, j, k) + u(i - 1, j + 1, k)) * (v(i - 1, j, k) + v(i, j, k));
    const Real vvyp = 0.25 * (v(i, j, k) + v(i, j + 1, k)) * (v(i, j, k) + v(i, j + 1, k));
    const Real vvym = 0.25 * (v(i, j - 1, k) + v(i, j, k)) * (v(i, j - 1, k) + v(i, j, k));
    const Real vwzp = 0.25 * (v(i, j, k) + v(i, j, k + 1)) * (w(i, j, k) + w(i, j + 1, k));
    const Real vwzm = 0.25 * (v(i, j, k - 1) + v(i, j, k)) * (w(i, j, k - 1) + w(i, j + 1, k - 1));
    return (uvxp - uvxm) * idx + (vvyp - vvym) * idy + (vwzp - vwzm) * idz;
  }

  // div(u w) of z-momentum at face (i, j, k+1/2)
  template <class V>
  KOKKOS_INLINE_FUNCTION Real adv_w(const V& u, const V& v, const V& w, int i, int j, int k) const {
    const Real uwxp = 0.25 * (u(i, j, k) + u(i, j, k + 1)) * (w(i, j, k) + w(i + 1, j, k));
    const Real uwxm = 0.25 * (u(i - 1, j, k) + u(i - 1, j, k + 1)) * (w(i - 1, j, k) + w(i, j, k));
    const Real vwyp = 0.25 * (v(i, j, k) + v(i, j, k + 1)) * (w(i, j, k) + w(i, j + 1, k));
    const Real vwym = 0.25 * (v(i, j - 1, k) + v(i, j - 1, k + 1)) * (w(i, j - 1, k) + w(i, j, k));
    const Real wwzp = 0.25 * (w(i, j, k) + w(i, j, k + 1)) * (w(i, j, k) + w(i, j, k + 1));
    const Real wwzm = 0.25 * (w(i, j, k - 1) + w(i, j, k)) * (w(i, j, k - 1) + w(i, j, k));
    return (uwxp - uwxm) * idx + (vwyp - vwym) * idy + (wwzp - wwzm) * idz;
  }

  template <class V>
  KOKKOS_INLINE_FUNCTION Real lap(const V& f, int i, int j, int k) const {
    const Real c = f(i, j, k);
    return (f(i + 1, j, k) - 2 * c + f(i - 1, j, k)) * idx * idx +
           (f(i, j + 1, k) - 2 * c + f(i, j - 1, k)) * idy * idy +
           (f(i, j, k + 1) - 2 * c + f(i, j, k - 1)) * idz * idz;
  }
};

// Fills rhs with N(u) at time t on the interior unknowns (v without the walls).
inline void momentum_rhs(const Grid& g, const FlowState& s, Real nu, const Manufactured& mms, Real t,
                         const MomentumRhs& rhs) {
  const AdvectionDiffusion op{1 / g.dx, 1 / g.dy, 1 / g.dz};
  auto u = s.u, v = s.v, w = s.w;
  auto ru = rhs.u, rv = rhs.v, rw = rhs.w;
  const int vtop = Grid::ng + g.ny - 1;  // the top wall's v is not an unknown
  par_for(
      "momentum_rhs", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        ru(i, j, k) = -op.adv_u(u, v, w, i, j, k) + nu * op.lap(u, i, j, k);
        rw(i, j, k) = -op.adv_w(u, v, w, i, j, k) + nu * op.lap(w, i, j, k);
        rv(i, j, k) = j < vtop ? -op.adv_v(u, v, w, i, j, k) + nu * op.lap(v, i, j, k) : Real(0);
      });
  // a separate loop, so the transcendental calls do not keep the one above
  // from vectorising in production runs
  if (mms.enabled)
    par_for(
        "momentum_mms_forcing", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
          ru(i, j, k) += mms.force(0, g.xf(i), g.yc(j), g.zc(k), t);
          rw(i, j, k) += mms.force(2, g.xc(i), g.yc(j), g.zf(k), t);
          if (j < vtop) rv(i, j, k) += mms.force(1, g.xc(i), g.yf(j), g.zc(k), t);
        });
}

}  // namespace softflow

#include "mixture_stress.hpp"

namespace softflow {

// The mixture's viscous term in excess of the fluid's, added to rhs:
//   div(2 mu(phi) D) / rho - nu_f L u
// so that momentum_rhs(nu_f) plus this is N(u) of the one-continuum mixture
// (the elastic force is added separately, Crank-Nicolson across the stage).
// It vanishes (to round-off: nu_f grad div u) where phi = 0 around the face,
// so `region` needs to cover phi's support and one cell more.
inline void momentum_viscous_excess(const Grid& g, const FlowState& s, const MixtureStress& st,
                                    const StoredNu& n, const MomentumRhs& rhs, const Range3& region) {
  const AdvectionDiffusion op{1 / g.dx, 1 / g.dy, 1 / g.dz};
  auto u = s.u, v = s.v, w = s.w;
  auto ru = rhs.u, rv = rhs.v, rw = rhs.w;
  const int vtop = Grid::ng + g.ny - 1;
  const Real nu_f = st.nu_f;
  par_for(
      "momentum_viscous_excess", region, KOKKOS_LAMBDA(int i, int j, int k) {
        ru(i, j, k) += st.viscous_u(u, v, w, n, i, j, k) - nu_f * op.lap(u, i, j, k);
        rw(i, j, k) += st.viscous_w(u, v, w, n, i, j, k) - nu_f * op.lap(w, i, j, k);
        if (j < vtop) rv(i, j, k) += st.viscous_v(u, v, w, n, i, j, k) - nu_f * op.lap(v, i, j, k);
      });
}

}  // namespace softflow
