// Laminar plane Couette flow: the steady state and the start-up transient.
#include <gtest/gtest.h>

#include <cmath>

#include "diagnostics.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

// Start-up from rest, walls at y = +-h moving at +-V (exact series):
// u = V [eta + sum_n 2 (-1)^n / (n pi) sin(n pi eta) exp(-nu n^2 pi^2 t / h^2)]
double startup_exact(double y, double t, double h, double V, double nu) {
  const double eta = y / h;
  double s = eta;
  for (int n = 1; n < 20000; ++n) {
    const double d = std::exp(-nu * n * n * M_PI * M_PI * t / (h * h));
    if (d < 1e-20) break;
    s += 2 * (n % 2 ? -1.0 : 1.0) / (n * M_PI) * std::sin(n * M_PI * eta) * d;
  }
  return V * s;
}

}  // namespace

TEST(Couette, SteadyStateIsLinearWithUniformShearStress) {
  // h = 1, nu = 1: the slowest transient mode decays like exp(-pi^2 t),
  // below 1e-12 by t = 3
  Config c = couette_case(8, 16, 8);
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  run_to(s, 3.0);
  Diagnostics d(s);
  FlowProfiles p = d.profiles();
  const double tau = c.fluid.mu * c.shear_rate();
  double worst = 0;
  for (double sh : p.shear) worst = std::max(worst, std::abs(sh / tau - 1));
  EXPECT_LT(worst, 1e-10) << "sigma_12 / (mu gamma) - 1 at worst";
  double uerr = 0;
  for (size_t j = 0; j < p.y_centre.size(); ++j)
    uerr = std::max(uerr, std::abs(p.u_mean[j] - c.walls.velocity * p.y_centre[j] / c.h()));
  EXPECT_LT(uerr, 1e-10);
  FlowScalars f = d.scalars();
  EXPECT_NEAR(f.mu_eff, 1.0, 1e-10);
  EXPECT_NEAR(f.tau_bottom, f.tau_top, 1e-10);
}

TEST(Couette, LinearProfileIsAnExactDiscreteSteadyState) {
  Config c = couette_case(8, 12, 8, {"initial.type=\"couette\""});
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  for (int n = 0; n < 20; ++n) s.advance(s.stable_dt());
  Diagnostics d(s);
  FlowProfiles p = d.profiles();
  for (double sh : p.shear) EXPECT_NEAR(sh, 1.0, 1e-12);
  EXPECT_LT(d.scalars().max_div, 1e-12);
}

TEST(Couette, StartupTransientConvergesAtSecondOrderInY) {
  const double t_end = 0.1;  // in h^2 / nu
  std::vector<double> hs, errs;
  for (int ny : {16, 32, 64}) {
    Config c = couette_case(8, ny, 8);
    FlowSolver s(c, MPI_COMM_WORLD);
    s.initialize();
    run_to(s, t_end);
    FlowProfiles p = Diagnostics(s).profiles();
    double e = 0;
    for (size_t j = 0; j < p.y_centre.size(); ++j)
      e = std::max(e, std::abs(p.u_mean[j] - startup_exact(p.y_centre[j], t_end, 1, 1, 1)));
    hs.push_back(s.grid().dy);
    errs.push_back(e);
    if (world_rank() == 0) std::printf("  ny = %3d  max error %.3e\n", ny, e);
  }
  const double q = order(hs, errs);
  if (world_rank() == 0) std::printf("  observed order in y: %.3f\n", q);
  EXPECT_GT(q, 1.9);
  EXPECT_LT(q, 2.2);
  EXPECT_LT(errs.back(), 1e-3);
}
