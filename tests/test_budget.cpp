// The stress diagnostics on problems with known answers.
//  1. A gap filled with solid (phi = 1) sheared uniformly from the Couette
//     profile: the stress is uniform, so the profile stays linear and the
//     solid is in simple shear of amount kappa = gamma t: B_12 = kappa,
//     B_11 = 1 + kappa^2. Elastic shear stress G kappa, viscous K mu_f gamma,
//     N1 = G kappa^2, N2 = 0, exactly (RK3 integrates the quadratic exactly);
//     all of N1 is elastic (simple shear has no viscous normal stresses).
//  2. A neo-Hookean layer |y| < a bonded between two Newtonian layers in
//     steady Couette flow: the total shear stress is uniform across the gap,
//     carried by the fluid viscous term outside the layer and by the elastic
//     term inside it; the Reynolds terms vanish (the flow is 1-D).
#include <gtest/gtest.h>

#include <numeric>

#include "diagnostics.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
void fill_with_solid(FlowSolver& s) {
  const Field3 phi = s.solid()->fields().q[0];
  par_for(
      "test_fill_solid", s.grid().all(), KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) = 1; });
  s.solid()->fill_ghosts();
  s.solid()->init_force();
}
}  // namespace

TEST(Budget, UniformlyShearedSolidHasTheExactStresses) {
  const double G = 3, K = 2, mu = 1, gamma = 1, t_end = 0.7;
  Config c = couette_case(
      6, 16, 6,
      {"grid.lx=1.5", "grid.lz=1.5", "particles.shape=layer", "particles.layer_thickness=1.0",
       "particles.shear_modulus=3.0", "particles.viscosity_ratio=2.0", "initial.type=\"couette\"",
       // RK3 integrates B's quadratic exactly only without the per-stage det
       // B = 1 projection: its stage values are not simple shears, and
       // projecting them moves the result by ~1e-7 (measured 2.3e-7 here)
       "particles.unimodular_b=false"});
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  fill_with_solid(s);
  run_to(s, t_end);
  Diagnostics d(s);
  const FlowProfiles p = d.profiles();
  const FlowScalars f = d.scalars();
  const double kappa = gamma * t_end, unit = mu * gamma;
  double worst = 0;
  for (size_t r = 0; r < p.y_face.size(); ++r) {
    worst = std::max(worst, std::abs(p.budget[particle_elastic][r] - G * kappa));
    worst = std::max(worst, std::abs(p.budget[particle_viscous][r] - K * mu * gamma));
    worst = std::max(worst, std::abs(p.budget[fluid_viscous][r]));
    worst = std::max(worst, std::abs(p.budget[fluid_reynolds][r]) + std::abs(p.budget[particle_reynolds][r]));
  }
  if (world_rank() == 0)
    std::printf(
        "  budget profiles off by <= %.1e; N1 = %.12f (exact %.12f), N2 = %.1e, mu_eff = %.12f (exact "
        "%.12f)\n",
        worst, f.n1, G * kappa * kappa / unit, f.n2, f.mu_eff, (K * mu + G * kappa) / unit);
  EXPECT_LT(worst, 1e-10);
  EXPECT_NEAR(f.n1, G * kappa * kappa / unit, 1e-10);
  EXPECT_NEAR(f.n1_elastic, G * kappa * kappa / unit, 1e-10);
  EXPECT_NEAR(f.n2, 0.0, 1e-10);
  EXPECT_NEAR(f.mu_eff, (K * mu + G * kappa) / unit, 1e-10);
  EXPECT_NEAR(f.particle_elastic, G * kappa / unit, 1e-10);
  EXPECT_NEAR(f.particle_viscous, K, 1e-10);
}

TEST(Budget, SteadyFluidSolidSandwich) {
  const double mu = 1, V = 1, h = 1, a = 0.5;
  Config c = couette_case(
      6, 32, 6,
      {"grid.lx=1.5", "grid.lz=1.5", "particles.shape=layer", "particles.layer_thickness=1.0",
       "particles.shear_modulus=4.0", "particles.viscosity_ratio=1.0", "time.viscous=\"implicit\""});
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  run_to(s, 15.0);  // the slowest elastic-viscous mode decays like exp(-t / ~1.5)
  Diagnostics d(s);
  const FlowProfiles p = d.profiles();
  const FlowScalars f = d.scalars();
  const double tau_sharp = mu * 2 * V / (2 * (h - a)), tau = 0.5 * (f.tau_bottom + f.tau_top);
  double worst_total = 0, worst_fluid = 0, worst_solid = 0;
  for (size_t r = 0; r < p.y_face.size(); ++r) {
    double total = 0;
    for (int b = 0; b < n_budget; ++b) total += p.budget[b][r];
    worst_total = std::max(worst_total, std::abs(total / tau - 1));
    const double y = std::abs(p.y_face[r]);
    if (y > a + 2 * s.grid().dy)
      worst_fluid = std::max(worst_fluid, std::abs(p.budget[fluid_viscous][r] / tau - 1));
    if (y < a - 2 * s.grid().dy)
      worst_solid = std::max(worst_solid, std::abs(p.budget[particle_elastic][r] / tau - 1));
  }
  if (world_rank() == 0)
    std::printf(
        "  |total / tau_wall - 1| <= %.1e; fluid layers %.1e, solid layer (elastic) %.1e; "
        "mu_eff %.4f (sharp interface %.4f); N2 = %.1e\n",
        worst_total, worst_fluid, worst_solid, f.mu_eff, tau_sharp / (mu * V / h), f.n2);
  // the momentum balance: uniform total shear stress (measured 2e-5 at t = 15)
  EXPECT_LT(worst_total, 1e-3);
  // away from the interface cells the fluid layers carry it alone. In the
  // solid layer the elastic term carries it only on average: the layer holds
  // a spurious odd-even (2 dy) velocity mode, seeded at the interfaces, that
  // the centred velocity gradient of B's source does not see, so a frozen
  // alternating B_12 and an alternating viscous stress balance each other
  // (measured 6% of tau with both viscous schemes alike; README, known limits)
  EXPECT_LT(worst_fluid, 1e-3);
  // the interface edges hold a half-solid mixture, so the solid acts about a
  // cell thicker: a first-order error (measured 6% at 16 cells per unit)
  EXPECT_NEAR(f.mu_eff, tau_sharp / (mu * V / h), 0.1 * tau_sharp / (mu * V / h));
  EXPECT_NEAR(f.n2, 0.0, 1e-10);
  // the budget's gap averages: the Reynolds terms vanish in this 1-D flow
  EXPECT_NEAR(f.fluid_reynolds, 0.0, 1e-10);
  EXPECT_NEAR(f.particle_reynolds, 0.0, 1e-10);
}
