// The hard cases (dense, stiff, strong viscosity contrast, large
// deformation) at reduced resolution: a short run stays finite and bounded.
// The same files in cases/hard/ run for many strain units as long checks.
#include <gtest/gtest.h>

#include "diagnostics.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

// (case, viscous scheme): 40 explicit steps (strain 0.005-0.05), or the
// implicit scheme to strain 0.4 (10-96 steps), at K = 0.01 and K = 10 among others
class HardCase : public ::testing::TestWithParam<std::tuple<const char*, const char*>> {};

TEST_P(HardCase, ShortRunStaysFiniteBoundedAndConservative) {
  const auto [name, scheme] = GetParam();
  const std::string file = std::string(SOFTFLOW_SOURCE_DIR) + "/cases/hard/" + name + ".toml";
  Config c =
      load_config(file, {"output.dir=\"stability-output\"", "time.viscous=\"" + std::string(scheme) + "\""});
  resolve_rank_grid(c, world_size());
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  Diagnostics d(s);
  const FlowScalars f0 = d.scalars();
  const bool implicit = std::string(scheme) == "implicit";
  const int steps = 40;
  const double strain = 0.4;
  double worst_detb = 0;
  long fallback = 0;
  for (int n = 0; implicit ? s.time * c.shear_rate() < strain : n < steps; ++n) {
    s.advance(s.stable_dt());
    if (n % 10 == 9 || implicit) {
      FlowScalars f = d.scalars();
      ASSERT_TRUE(std::isfinite(f.kinetic_energy)) << "step " << s.step;
      // det B before the unimodular projection, over every stage since the last call
      worst_detb = std::max({worst_detb, std::abs(f.detb_raw_min - 1), std::abs(f.detb_raw_max - 1)});
      fallback += f.b_fallback_cells;
    }
  }
  const FlowScalars f = d.scalars();
  if (world_rank() == 0)
    std::printf(
        "  %s, %s viscosity: %ld steps to strain %.3f, mu_eff %.3f, phi in [%g, %g], |det B - 1| <= %.2e "
        "before the projection, %ld fallback cell-stages, volume drift %.1e\n",
        name, scheme, s.step, s.time * c.shear_rate(), f.mu_eff, f.phi_min, f.phi_max, worst_detb, fallback,
        f.solid_volume / f0.solid_volume - 1);
  EXPECT_TRUE(std::isfinite(f.mu_eff));
  // phi is kept in [0, 1] exactly by the conservative redistribution
  EXPECT_GE(f.phi_min, 0.0);
  EXPECT_LE(f.phi_max, 1.0);
  // the flux form conserves solid volume to round-off
  EXPECT_NEAR(f.solid_volume / f0.solid_volume, 1.0, 1e-12);
  // det B = 1 in an incompressible solid. Read before the unimodular
  // projection (after it det B = 1 by construction), at every RK3 stage: the
  // issue-12 bound [0.97, 1.03]. Measured: below 6e-5 over the explicit
  // steps, 1.4e-3 to 1.9e-2 with the implicit scheme's large steps. The
  // first-order B fallback (kernels/solid_b_fallback.hpp) may act only there:
  // it takes cells whose det B moved by more than 0.02 in one stage, which
  // strain steps of 0.001 cannot do (phi033_ca2 at strain steps of 0.04 from
  // rest: 244 cell-stages).
  EXPECT_LT(worst_detb, 0.03);
  if (!implicit) EXPECT_EQ(fallback, 0);
  // the projection keeps the velocity divergence-free
  EXPECT_LT(f.max_div * std::min({s.grid().dx, s.grid().dy, s.grid().dz}) / f.max_speed, 1e-12);
}

INSTANTIATE_TEST_SUITE_P(Cases, HardCase,
                         ::testing::Combine(::testing::Values("phi033_ca002", "phi011_ca02_k001",
                                                              "phi011_ca02_k10", "phi033_ca2"),
                                            ::testing::Values("explicit", "implicit")));
