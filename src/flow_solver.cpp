#include "flow_solver.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "../kernels/momentum_rhs.hpp"
#include "../kernels/projection.hpp"
#include "../kernels/rk3_update.hpp"
#include "../kernels/timestep_limits.hpp"
#include "../kernels/wall_bc.hpp"

namespace softflow {

const char* to_string(DtLimit l) {
  switch (l) {
    case DtLimit::advective: return "advective";
    case DtLimit::viscous: return "viscous";
    case DtLimit::elastic: return "elastic";
    case DtLimit::dt_max: return "dt_max";
    case DtLimit::end_time: return "end";
  }
  return "?";
}

FlowSolver::FlowSolver(const Config& cfg, MPI_Comm comm)
    : cfg_(cfg),
      dec_(comm, cfg),
      grid_(dec_.grid(cfg)),
      state_(grid_),
      rhs_now_(grid_, "rhs_now"),
      rhs_before_(grid_, "rhs_before"),
      halo_(dec_, grid_),
      poisson_(dec_, grid_) {
  if (cfg.initial.type == "manufactured") {
    mms_.enabled = true;
    mms_.amp = cfg.initial.amplitude;
    mms_.omega = cfg.initial.omega;
    mms_.a = 2 * M_PI / cfg.grid.lx;
    mms_.c = 2 * M_PI / cfg.grid.lz;
    mms_.h = cfg.h();
    mms_.vw = cfg.walls.velocity;
    mms_.nu = cfg.nu();
  }
  if (cfg.particles.enabled) solid_ = std::make_unique<SolidPhase>(cfg_, grid_, halo_);
}

Real FlowSolver::wall_velocity(Real t) const {
  const Real vw = cfg_.walls.velocity, om = cfg_.walls.omega;
  return om > 0 ? vw * std::cos(om * t) : vw;
}

void FlowSolver::fill_velocity_ghosts(Real t) {
  halo_.exchange({state_.u, state_.v, state_.w});
  apply_velocity_walls(grid_, state_, wall_velocity(t));
}

void FlowSolver::fill_pressure_ghosts() {
  halo_.exchange({state_.p});
  apply_pressure_walls(grid_, state_.p);
}

void FlowSolver::initialize() {
  const Grid g = grid_;
  auto u = state_.u, v = state_.v, w = state_.w;
  Kokkos::deep_copy(u, 0.0);
  Kokkos::deep_copy(v, 0.0);
  Kokkos::deep_copy(w, 0.0);
  Kokkos::deep_copy(state_.p, 0.0);
  const std::string& type = cfg_.initial.type;
  if (type == "couette") {
    const Real vw = cfg_.walls.velocity, h = g.h();
    par_for("init_couette", g.interior(),
            KOKKOS_LAMBDA(int i, int j, int k) { u(i, j, k) = vw * g.yc(j) / h; });
  } else if (type == "manufactured") {
    const Manufactured m = mms_;
    const int vtop = Grid::ng + g.ny - 1;
    par_for("init_manufactured", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
      u(i, j, k) = m.eval(g.xf(i), g.yc(j), g.zc(k), 0).u;
      w(i, j, k) = m.eval(g.xc(i), g.yc(j), g.zf(k), 0).w;
      if (j < vtop) v(i, j, k) = m.eval(g.xc(i), g.yf(j), g.zc(k), 0).v;
    });
  }
  time = 0;
  step = 0;
  fill_velocity_ghosts();
  project(1.0, time);  // the sampled field is divergence-free only to truncation error
  if (solid_) {
    solid_->seed();
    solid_->init_force();
  }
}

Real FlowSolver::stable_dt(DtLimit* which) {
  // RK3 is stable for imaginary eigenvalues up to sqrt(3) and negative real
  // ones down to -2.51; the 7-point Laplacian's extreme eigenvalue is
  // -4 nu (1/dx^2 + 1/dy^2 + 1/dz^2).
  Real rate = max_advective_rate(grid_, state_);
  MPI_Allreduce(MPI_IN_PLACE, &rate, 1, MPI_DOUBLE, MPI_MAX, dec_.comm);
  const Grid& g = grid_;
  const Real dt_adv = rate > 0 ? std::sqrt(3.0) / rate : 1e300;
  const Real dt_visc =
      2.51 / (4 * cfg_.nu() * (1 / (g.dx * g.dx) + 1 / (g.dy * g.dy) + 1 / (g.dz * g.dz)));
  Real dt = cfg_.time.cfl * std::min(dt_adv, dt_visc);
  DtLimit l = dt_adv < dt_visc ? DtLimit::advective : DtLimit::viscous;
  if (solid_) {
    // the mixture's largest viscosity sets the viscous limit; elastic waves their own
    const Real kmax = std::max(Real(1), cfg_.particles.viscosity_ratio);
    const Real dt_v = dt_visc / kmax, dt_e = solid_->elastic_dt();
    const Real lim = std::min({dt_adv, dt_v, dt_e});
    dt = cfg_.time.cfl * lim;
    l = lim == dt_adv ? DtLimit::advective : lim == dt_v ? DtLimit::viscous : DtLimit::elastic;
  }
  if (cfg_.time.dt_max < dt) {
    dt = cfg_.time.dt_max;
    l = DtLimit::dt_max;
  }
  if (which) *which = l;
  return dt;
}

// u = u* - adt grad(phi), with the walls' ghosts at time t_wall
void FlowSolver::project(Real adt, Real t_wall) {
  divergence_to_poisson(grid_, state_, adt, poisson_.rhs());
  poisson_.solve();
  poisson_to_field(grid_, poisson_.rhs(), state_.p);
  fill_pressure_ghosts();
  correct_velocity(grid_, state_, adt);
  fill_velocity_ghosts(t_wall);
}

// One RK3 step. Each stage: the explicit right-hand side from the previous
// stage's fields; with particles, phi and B advanced first and their elastic
// force taken Crank-Nicolson across the stage; then the projection.
void FlowSolver::advance(Real dt) {
  const Real nu = cfg_.nu();
  for (int s = 0; s < Rk3::stages; ++s) {
    const Real gdt = Rk3::gamma[s] * dt, zdt = Rk3::zeta[s] * dt, adt = Rk3::alpha[s] * dt;
    const Real t_end = time + Rk3::c_end[s] * dt;
    if (solid_) {
      momentum_rhs_mixture(grid_, state_, solid_->stress(), solid_->fields().phi(), rhs_now_);
      solid_->advance_stage(state_, gdt, zdt);
      rk3_update_cn(grid_, state_, rhs_now_, rhs_before_, gdt, zdt, solid_->force_now(),
                    solid_->force_before(), adt / 2);
      solid_->end_stage();
    } else {
      momentum_rhs(grid_, state_, nu, mms_, time + Rk3::c[s] * dt, rhs_now_);
      rk3_update(grid_, state_, rhs_now_, rhs_before_, gdt, zdt);
    }
    fill_velocity_ghosts(t_end);
    project(adt, t_end);
    std::swap(rhs_now_, rhs_before_);
  }
  time += dt;
  ++step;
}

}  // namespace softflow
