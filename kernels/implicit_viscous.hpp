// The implicit viscous step: Crank-Nicolson across each RK3 stage for a
// constant-coefficient part nu0 L of the viscous term, the rest explicit.
//
// Stage s (alpha = gamma + zeta, beta = alpha dt nu0 / 2):
//   (I - beta L) u* = u + gdt N + zdt N_before + cdt (F + F_before)
//                     + adt R(u) + beta L u - adt grad p
// N: advection (+ manufactured forcing), RK3-weighted; F: the hyper-elastic
// force, Crank-Nicolson (cdt = adt / 2); p: the pressure of the last stage
// (incremental projection, as CaNS); R = div(2 nu(phi) D) - nu0 L u, the
// variable part of the mixture viscosity, with phi already advanced to the
// stage's end (phi and B are advanced first, for the elastic force).
//
// Why R is weighted alpha dt per stage (forward Euler) and not (gdt, zdt):
// with nu0 >= max nu, per Fourier mode the stage factor tends to
// 1 - 2 nu / nu0 in [-1, 1] for any dt; with the RK3 weights the step is
// unstable for 0.06 < nu / nu0 < 0.63 at large dt (tests/test_implicit.cpp
// maps both). Choosing nu0 = max(mu_f, mu_s) / rho makes the split stable for
// every K. R vanishes for K = 1 and without particles, where the scheme is
// second order in time.
#pragma once
#include "../src/poisson.hpp"
#include "flow_state.hpp"
#include "mixture_stress.hpp"
#include "momentum_rhs.hpp"

namespace softflow {

// The weights of one implicit stage and the walls' velocities at its end.
struct ImplicitStage {
  Real gdt = 0, zdt = 0, cdt = 0, adt = 0;
  Real beta = 0;         // alpha dt nu0 / 2
  Real nu0 = 0;          // the implicit (constant) kinematic viscosity
  Real wall_bottom = 0;  // u at y = -h at the stage's end
  Real wall_top = 0;     // u at y = +h at the stage's end
};

// What the stage's right-hand side is made of; force_* and phi are empty
// without particles.
struct StageTerms {
  MomentumRhs now, before;              // N at this and the previous stage
  MomentumRhs force_now, force_before;  // elastic force, end and start of the stage
  Field3 phi;                           // solid fraction (empty: no particles)
  MixtureStress stress;                 // the mixture's stress operators (for R)
  StoredNu nu;                          // nu(phi) around solid_region (for R)
  Range3 solid_region{};                // where F or R can be nonzero
  bool remainder = true;                // false: R = 0 (nu(phi) = nu0 everywhere, K = 1)
};

// The three Helmholtz right-hand sides, in the Poisson solver's y-pencil order.
inline void implicit_predictor(const Grid& g, const FlowState& s, const StageTerms& t, const ImplicitStage& c,
                               const Array1& ru, const Array1& rv, const Array1& rw) {
  const AdvectionDiffusion op{1 / g.dx, 1 / g.dy, 1 / g.dz};
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl, vtop = Grid::ng + g.ny - 1;
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  // the known wall values of the first and last rows of u (w's are 0)
  const Real wall_lo = 2 * c.beta * idy * idy * c.wall_bottom, wall_hi = 2 * c.beta * idy * idy * c.wall_top;
  const bool solid = t.phi.size() > 0;
  auto u = s.u, v = s.v, w = s.w, p = s.p, phi = t.phi;
  auto nu = t.now.u, nv = t.now.v, nw = t.now.w, bu = t.before.u, bv = t.before.v, bw = t.before.w;
  auto fu = t.force_now.u, fv = t.force_now.v, fw = t.force_now.w;
  auto eu = t.force_before.u, ev = t.force_before.v, ew = t.force_before.w;
  const MixtureStress st = t.stress;
  const StoredNu n = t.nu;
  par_for(
      "implicit_predictor", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const long m = PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl);
        Real xu = u(i, j, k) + c.gdt * nu(i, j, k) + c.zdt * bu(i, j, k) + c.beta * op.lap(u, i, j, k) -
                  c.adt * (p(i + 1, j, k) - p(i, j, k)) * idx;
        Real xw = w(i, j, k) + c.gdt * nw(i, j, k) + c.zdt * bw(i, j, k) + c.beta * op.lap(w, i, j, k) -
                  c.adt * (p(i, j, k + 1) - p(i, j, k)) * idz;
        Real xv = 0;
        if (j < vtop)
          xv = v(i, j, k) + c.gdt * nv(i, j, k) + c.zdt * bv(i, j, k) + c.beta * op.lap(v, i, j, k) -
               c.adt * (p(i, j + 1, k) - p(i, j, k)) * idy;
        if (j == ng) xu += wall_lo;
        if (j == vtop) xu += wall_hi;
        ru(m) = xu;
        rv(m) = xv;
        rw(m) = xw;
      });
  if (!solid) return;
  if (!t.remainder) {
    par_for(
        "implicit_predictor_force", t.solid_region, KOKKOS_LAMBDA(int i, int j, int k) {
          const long m = PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl);
          ru(m) += c.cdt * (fu(i, j, k) + eu(i, j, k));
          rw(m) += c.cdt * (fw(i, j, k) + ew(i, j, k));
          if (j < vtop) rv(m) += c.cdt * (fv(i, j, k) + ev(i, j, k));
        });
    return;
  }
  // the elastic force and the viscous remainder R, only where they can be nonzero
  par_for(
      "implicit_predictor_solid", t.solid_region, KOKKOS_LAMBDA(int i, int j, int k) {
        const long m = PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl);
        ru(m) += c.cdt * (fu(i, j, k) + eu(i, j, k)) +
                 c.adt * (st.viscous_u(u, v, w, n, i, j, k) - c.nu0 * op.lap(u, i, j, k));
        rw(m) += c.cdt * (fw(i, j, k) + ew(i, j, k)) +
                 c.adt * (st.viscous_w(u, v, w, n, i, j, k) - c.nu0 * op.lap(w, i, j, k));
        if (j < vtop)
          rv(m) += c.cdt * (fv(i, j, k) + ev(i, j, k)) +
                   c.adt * (st.viscous_v(u, v, w, n, i, j, k) - c.nu0 * op.lap(v, i, j, k));
      });
}

// u, v, w from the solved y-pencil arrays (v's top wall row is not an unknown)
inline void implicit_to_velocity(const Grid& g, const FlowState& s, const Array1& ru, const Array1& rv,
                                 const Array1& rw) {
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl, vtop = Grid::ng + g.ny - 1;
  auto u = s.u, v = s.v, w = s.w;
  par_for(
      "implicit_copy_velocity", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const long m = PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl);
        u(i, j, k) = ru(m);
        w(i, j, k) = rw(m);
        if (j < vtop) v(i, j, k) = rv(m);
      });
}

// p += phi - beta L phi: the pressure update of the incremental projection
// with implicit viscosity (phi's ghosts must be set)
inline void pressure_increment(const Grid& g, const Field3& p, const Field3& phi, Real beta) {
  const AdvectionDiffusion op{1 / g.dx, 1 / g.dy, 1 / g.dz};
  par_for(
      "implicit_pressure_update", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k) { p(i, j, k) += phi(i, j, k) - beta * op.lap(phi, i, j, k); });
}

}  // namespace softflow
