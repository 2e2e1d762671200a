// Flow diagnostics, reduced over all ranks: plane averages across the gap and
// the scalars of the time series. Shear stress is sigma_12 of the fluid,
// mu (du/dy + dv/dx), on the y-faces (edges of the MAC grid), so its first
// and last entries are the stresses on the bottom and top walls.
#pragma once
#include <vector>

#include "flow_solver.hpp"

namespace softflow {

struct FlowScalars {
  Real kinetic_energy = 0;  // volume average of |u|^2 / 2 (per unit density)
  Real max_div = 0;         // max |div u| over cells
  Real max_speed = 0;       // max |u_i| over faces, any component
  Real tau_bottom = 0;      // <sigma_12> on the bottom wall
  Real tau_top = 0;         // <sigma_12> on the top wall
  Real mu_eff = 0;          // (tau_bottom + tau_top) / 2 / (mu_f gamma), 0 if gamma = 0
  // solid phase (zero without particles)
  Real solid_volume = 0;    // sum of phi dV (unclamped: conserved to round-off)
  Real phi_min = 0, phi_max = 0;
  Real detb_min = 1, detb_max = 1;  // det B over cells with phi > 0.5 (exactly 1 in theory)
};

struct FlowProfiles {
  std::vector<Real> y_centre, u_mean;  // ny cell centres
  std::vector<Real> y_face, shear;     // ny + 1 faces, walls included
};

class Diagnostics {
 public:
  explicit Diagnostics(FlowSolver& s);
  FlowScalars scalars();
  void solid_scalars(FlowScalars& f);
  FlowProfiles profiles();

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void plane_sums();  // fills sums_ (device) and reduces over ranks into host_

 private:
  FlowSolver& s_;
  Kokkos::View<Real**, Kokkos::LayoutLeft, MemSpace> sums_;  // (row, quantity)
  Kokkos::View<Real**, Kokkos::LayoutLeft, Kokkos::HostSpace> host_;
};

}  // namespace softflow
