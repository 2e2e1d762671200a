#include "flow_solver.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "../kernels/implicit_viscous.hpp"
#include "../kernels/momentum_rhs.hpp"
#include "../kernels/projection.hpp"
#include "../kernels/rk3_update.hpp"
#include "../kernels/timestep_limits.hpp"
#include "../kernels/wall_bc.hpp"

namespace softflow {

const char* to_string(DtLimit l) {
  switch (l) {
    case DtLimit::advective:
      return "advective";
    case DtLimit::viscous:
      return "viscous";
    case DtLimit::elastic:
      return "elastic";
    case DtLimit::dt_max:
      return "dt_max";
    case DtLimit::end_time:
      return "end";
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
  if (cfg.particles.enabled) {
    solid_ = std::make_unique<SolidPhase>(cfg_, grid_, halo_);
    solid_->use_poisson(poisson_);
  }
  if (cfg.time.implicit_viscous()) {
    implicit_ = true;
    const Real k = cfg.particles.enabled ? cfg.particles.viscosity_ratio : Real(1);
    nu0_ = cfg.nu() * std::max(Real(1), k);
    const size_t n = poisson_.rhs().size();
    helm_u_ = Array1("implicit_rhs_u", n);
    helm_v_ = Array1("implicit_rhs_v", n);
    helm_w_ = Array1("implicit_rhs_w", n);
    dp_ = Field3("pressure_increment", grid_.sx(), grid_.sy(), grid_.sz());
  }
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
    par_for(
        "init_couette", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) { u(i, j, k) = vw * g.yc(j) / h; });
  } else if (type == "manufactured") {
    const Manufactured m = mms_;
    const int vtop = Grid::ng + g.ny - 1;
    par_for(
        "init_manufactured", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
          u(i, j, k) = m.eval(g.xf(i), g.yc(j), g.zc(k), 0).u;
          w(i, j, k) = m.eval(g.xc(i), g.yc(j), g.zf(k), 0).w;
          if (j < vtop) v(i, j, k) = m.eval(g.xc(i), g.yf(j), g.zc(k), 0).v;
        });
  }
  time = 0;
  step = 0;
  fill_velocity_ghosts();
  project(1.0, time);  // the sampled field is divergence-free only to truncation error
  if (implicit_) {
    // the incremental projection needs the pressure itself: the exact one of
    // the manufactured solution, 0 for a fluid starting from rest or Couette
    auto p = state_.p;
    Kokkos::deep_copy(p, 0.0);
    if (mms_.enabled) {
      const Manufactured m = mms_;
      par_for(
          "init_manufactured_pressure", g.interior(),
          KOKKOS_LAMBDA(int i, int j, int k) { p(i, j, k) = m.eval(g.xc(i), g.yc(j), g.zc(k), 0).p; });
    }
    fill_pressure_ghosts();
  }
  if (solid_) {
    solid_->seed();
    solid_->init_force();
  }
}

Real FlowSolver::stable_dt(DtLimit* which) {
  // RK3 is stable for imaginary eigenvalues up to sqrt(3) and negative real
  // ones down to -2.51; the 7-point Laplacian's extreme eigenvalue is
  // -4 nu (1/dx^2 + 1/dy^2 + 1/dz^2).
  // the advective rate and, with particles, the solid's stretch (for the
  // elastic waves): one reduction over the ranks
  Real local[2] = {max_advective_rate(grid_, state_), solid_ ? solid_->max_stretch() : Real(1)};
  MPI_Allreduce(MPI_IN_PLACE, local, 2, MPI_DOUBLE, MPI_MAX, dec_.comm);
  Real rate = local[0];
  const Real stretch = local[1];
  const Grid& g = grid_;
  // implicit viscosity has no viscous limit; the walls' speed bounds the
  // advective rate from below, so a flow starting from rest gets a finite step
  if (implicit_) rate = std::max(rate, std::abs(cfg_.walls.velocity) / g.dx);
  const Real dt_adv = rate > 0 ? std::sqrt(3.0) / rate : 1e300;
  // with particles the mixture's largest viscosity sets the viscous limit
  const Real kmax = solid_ ? std::max(Real(1), cfg_.particles.viscosity_ratio) : Real(1);
  const Real dt_visc =
      implicit_ ? Real(1e300)
                : 2.51 / (4 * cfg_.nu() * kmax * (1 / (g.dx * g.dx) + 1 / (g.dy * g.dy) + 1 / (g.dz * g.dz)));
  const Real dt_el = solid_ ? solid_->elastic_dt(stretch) : Real(1e300);
  const Real lim = std::min({dt_adv, dt_visc, dt_el});
  Real dt = cfg_.time.cfl * lim;
  DtLimit l = lim == dt_adv ? DtLimit::advective : lim == dt_visc ? DtLimit::viscous : DtLimit::elastic;
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
  correct_velocity(grid_, state_, state_.p, adt);
  fill_velocity_ghosts(t_wall);
}

// Incremental projection (implicit viscosity): phi solves L phi = div u* / adt,
// u = u* - adt grad(phi), p += phi - beta L phi.
void FlowSolver::project_incremental(Real adt, Real beta, Real t_wall) {
  divergence_to_poisson(grid_, state_, adt, poisson_.rhs());
  poisson_.solve();
  poisson_to_field(grid_, poisson_.rhs(), dp_);
  halo_.exchange({dp_});
  apply_pressure_walls(grid_, dp_);
  correct_velocity(grid_, state_, dp_, adt);
  pressure_increment(grid_, state_.p, dp_, beta);
  fill_pressure_ghosts();
  fill_velocity_ghosts(t_wall);
}

// Explicit stage: the right-hand side from the previous stage's fields; with
// particles, phi and B advanced first and their elastic force taken
// Crank-Nicolson across the stage; then the projection.
void FlowSolver::explicit_stage(int s, Real dt) {
  const Real gdt = Rk3::gamma[s] * dt, zdt = Rk3::zeta[s] * dt, adt = Rk3::alpha[s] * dt;
  const Real t_end = time + Rk3::c_end[s] * dt;
  if (solid_) {
    // the fluid's terms over the box, the mixture's excess viscosity near the solid only
    momentum_rhs(grid_, state_, cfg_.nu(), mms_, time + Rk3::c[s] * dt, rhs_now_);
    if (!solid_->uniform_viscosity())
      momentum_viscous_excess(grid_, state_, solid_->stress(), solid_->viscosity(solid_->force_region()),
                              rhs_now_, solid_->force_region());
    solid_->advance_stage(state_, gdt, zdt, s == Rk3::stages - 1);
    rk3_update_cn(grid_, state_, rhs_now_, rhs_before_, gdt, zdt, solid_->force_now(), solid_->force_before(),
                  adt / 2);
    solid_->end_stage();
  } else {
    momentum_rhs(grid_, state_, cfg_.nu(), mms_, time + Rk3::c[s] * dt, rhs_now_);
    rk3_update(grid_, state_, rhs_now_, rhs_before_, gdt, zdt);
  }
  fill_velocity_ghosts(t_end);
  project(adt, t_end);
}

// Implicit stage (kernels/implicit_viscous.hpp): advection RK3-weighted, the
// constant viscosity nu0 Crank-Nicolson, the variable remainder forward
// Euler; one Helmholtz solve per component, then the incremental projection.
void FlowSolver::implicit_stage(int s, Real dt) {
  ImplicitStage c;
  c.gdt = Rk3::gamma[s] * dt, c.zdt = Rk3::zeta[s] * dt, c.adt = Rk3::alpha[s] * dt;
  c.cdt = c.adt / 2, c.nu0 = nu0_, c.beta = c.adt * nu0_ / 2;
  const Real t_end = time + Rk3::c_end[s] * dt;
  c.wall_bottom = -wall_velocity(t_end), c.wall_top = wall_velocity(t_end);
  momentum_rhs(grid_, state_, 0, mms_, time + Rk3::c[s] * dt, rhs_now_);  // advection (+ forcing)
  StageTerms t;
  t.now = rhs_now_, t.before = rhs_before_;
  if (solid_) {
    solid_->advance_stage(state_, c.gdt, c.zdt, s == Rk3::stages - 1);
    t.force_now = solid_->force_now(), t.force_before = solid_->force_before();
    t.phi = solid_->fields().phi(), t.stress = solid_->stress();
    // R = div(2 nu(phi) D) - nu0 L u vanishes away from the solid only if
    // nu0 = nu_f, and everywhere (to round-off) if nu(phi) = nu0 too (K = 1)
    t.solid_region = nu0_ == cfg_.nu() ? solid_->force_region() : grid_.interior();
    t.remainder = !(nu0_ == cfg_.nu() && solid_->uniform_viscosity());
    if (t.remainder) t.nu = solid_->viscosity(t.solid_region);
  }
  implicit_predictor(grid_, state_, t, c, helm_u_, helm_v_, helm_w_);
  if (solid_) solid_->end_stage();
  poisson_.solve(helm_u_, {1, -c.beta, WallRows::dirichlet_centre});
  poisson_.solve(helm_v_, {1, -c.beta, WallRows::dirichlet_face});
  poisson_.solve(helm_w_, {1, -c.beta, WallRows::dirichlet_centre});
  implicit_to_velocity(grid_, state_, helm_u_, helm_v_, helm_w_);
  fill_velocity_ghosts(t_end);
  project_incremental(c.adt, c.beta, t_end);
}

void FlowSolver::advance(Real dt) {
  if (solid_) solid_->begin_step();
  for (int s = 0; s < Rk3::stages; ++s) {
    if (implicit_)
      implicit_stage(s, dt);
    else
      explicit_stage(s, dt);
    std::swap(rhs_now_, rhs_before_);
  }
  time += dt;
  ++step;
}

}  // namespace softflow
