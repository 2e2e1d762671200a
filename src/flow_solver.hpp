// The single-phase Couette flow solver: state, work arrays and one RK3 step.
// Everything is allocated in the constructor; advance() allocates nothing.
#pragma once
#include <memory>

#include "../kernels/flow_state.hpp"
#include "../kernels/manufactured.hpp"
#include "decomposition.hpp"
#include "halo.hpp"
#include "poisson.hpp"
#include "solid_phase.hpp"

namespace softflow {

// Which limit set the time step (reported in the progress line).
enum class DtLimit { advective, viscous, elastic, dt_max, end_time };
const char* to_string(DtLimit l);

class FlowSolver {
 public:
  // cfg.parallel must already be resolved for the communicator's size
  FlowSolver(const Config& cfg, MPI_Comm comm);

  void initialize();                         // from cfg.initial, then project
  Real stable_dt(DtLimit* which = nullptr);  // cfl times the smallest stability limit
  void advance(Real dt);                     // one RK3 step: three stages, three projections
  bool implicit_viscous() const { return implicit_; }
  // the constant kinematic viscosity taken implicitly: max(mu_f, mu_s) / rho
  Real implicit_nu() const { return nu0_; }

  // fill x/z ghosts and the walls' ghosts of the velocity (walls at time t) and of p
  void fill_velocity_ghosts(Real t);
  void fill_velocity_ghosts() { fill_velocity_ghosts(time); }
  void fill_pressure_ghosts();
  // +-V_w, or +-V_w cos(omega t) for oscillating walls
  Real wall_velocity(Real t) const;
  // the solid phase, or nullptr for a case without particles
  SolidPhase* solid() { return solid_.get(); }
  const SolidPhase* solid() const { return solid_.get(); }

  const Config& config() const { return cfg_; }
  const Decomposition& decomposition() const { return dec_; }
  const Grid& grid() const { return grid_; }
  FlowState& state() { return state_; }
  const Manufactured& manufactured() const { return mms_; }
  PoissonSolver& poisson() { return poisson_; }
  Halo& halo() { return halo_; }

  Real time = 0;
  long step = 0;

 private:
  void explicit_stage(int s, Real dt);
  void implicit_stage(int s, Real dt);
  void project(Real adt, Real t_wall);
  void project_incremental(Real adt, Real beta, Real t_wall);
  Config cfg_;
  Decomposition dec_;
  Grid grid_;
  FlowState state_;
  MomentumRhs rhs_now_, rhs_before_;
  Halo halo_;
  PoissonSolver poisson_;
  Manufactured mms_;
  std::unique_ptr<SolidPhase> solid_;
  // implicit viscosity only: the Helmholtz right-hand sides (y-pencil order)
  // and the pressure increment of the incremental projection
  bool implicit_ = false;
  Real nu0_ = 0;
  Array1 helm_u_, helm_v_, helm_w_;
  Field3 dp_;
};

}  // namespace softflow
