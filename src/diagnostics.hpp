// Flow diagnostics, reduced over all ranks: plane averages across the gap and
// the scalars of the time series.
//
// Stresses are those of the mixture (METHOD.md), sigma = -p I + 2 mu(phi) D +
// phi G (B - I), mu(phi) = (1 - phi) mu_f + phi mu_s; G (B - I) everywhere
// (see kernels/mixture_stress.hpp). The shear-stress budget lives on the
// y-faces (the x-y edges of the MAC grid, where sigma_12 is computed), so its
// first and last entries are the walls:
//   fluid viscous      (1 - phi) mu_f (du/dy + dv/dx)
//   particle viscous   phi mu_s (du/dy + dv/dx)
//   particle elastic   phi G B_12
//   fluid Reynolds    -(1 - phi) rho u'v'
//   particle Reynolds -phi rho u'v'
// with phi the 4-cell edge average (as the momentum equation uses) and u' = u
// - <u>(y); v' = v since the plane mean of v is zero (div u = 0, v = 0 on the
// walls). The wall shear stress is the sum of the first three (the Reynolds
// terms vanish on the walls). N1 and N2 are box averages of sigma_11 -
// sigma_22 and sigma_22 - sigma_33 at the cell centres (the pressure cancels).
// Stresses are reported in units of mu_f gamma where gamma != 0.
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
  Real n1 = 0, n2 = 0;      // <<sigma_11 - sigma_22>>, <<sigma_22 - sigma_33>> / (mu_f gamma)
  // volume averages of the shear-stress budget / (mu_f gamma), over the gap
  Real fluid_viscous = 0, fluid_reynolds = 0, particle_viscous = 0, particle_reynolds = 0,
       particle_elastic = 0;
  // solid phase (zero without particles)
  Real solid_volume = 0;  // sum of phi dV (unclamped: conserved to round-off)
  Real phi_min = 0, phi_max = 0;
  Real detb_min = 1, detb_max = 1;  // det B over cells with phi > 0.5 (exactly 1 in theory)
  // the same over every stage since the previous row, before the unimodular
  // projection (src/solid_phase.hpp); the mean over those stages of the
  // share of the solid's elastic shear stress one projection removed
  // (signed); the share of the volume-summed elastic
  // shear stress phi G B_xy carried by cells with phi < 0.1
  Real detb_raw_min = 1, detb_raw_max = 1, unimodular_removed = 0, elastic_share_lowphi = 0;
  Real map_det_corrected = 0, map_volume_moved = 0;  // particles.solid_model = "reference_map"
  // particles.debris_return: the solid volume returned since the last row, relative
  Real debris_returned = 0;
  Real solid_share_lowphi = 0;  // share of the solid volume in cells with phi < 0.1 (shed wisps)
  // the elastic part of n1, <<phi G (B_11 - B_22)>> / (mu_f gamma); n1 minus it is
  // the viscous part (at K != 1 the two nearly cancel, so each part's
  // convergence is measured on its own)
  Real n1_elastic = 0;
  // cell-stages whose B took the first-order fallback since the previous row
  // (kernels/solid_b_fallback.hpp), over all ranks
  long b_fallback_cells = 0;
};

// Budget terms, in the order of the comment above.
enum BudgetTerm {
  fluid_viscous,
  particle_viscous,
  particle_elastic,
  fluid_reynolds,
  particle_reynolds,
  n_budget
};
const char* budget_name(int term);

struct FlowProfiles {
  std::vector<Real> y_centre, u_mean, phi_mean;  // ny cell centres
  std::vector<Real> y_face, shear;               // ny + 1 faces, walls included; shear = total
  std::vector<Real> budget[n_budget];            // ny + 1 faces, physical units
};

class Diagnostics {
 public:
  explicit Diagnostics(FlowSolver& s);
  // profiles: if given, the profiles the scalars were computed from (a
  // profiles row on the same step need not sum the planes again)
  FlowScalars scalars(FlowProfiles* profiles = nullptr);
  void solid_scalars(FlowScalars& f);
  FlowProfiles profiles();

  // public only because nvcc forbids extended (KOKKOS_LAMBDA) lambdas in
  // private or protected member functions
  void plane_sums();  // fills sums_ (device) and reduces over ranks into host_
  // box means of sigma_11 - sigma_22, sigma_22 - sigma_33 and the elastic part of the first
  void normal_stress_differences(Real& n1, Real& n2, Real& n1_elastic);

 private:
  FlowSolver& s_;
  Kokkos::View<Real**, Kokkos::LayoutLeft, MemSpace> sums_;  // (row, quantity)
  Kokkos::View<Real**, Kokkos::LayoutLeft, Kokkos::HostSpace> host_;
};

}  // namespace softflow
