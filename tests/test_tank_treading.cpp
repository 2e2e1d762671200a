// The solid phase stays physical while a sphere tank-treads (issue 12): one
// neo-Hookean sphere (Ca = 0.2, K = 1, Re = 0.1) at 4 points per radius in a
// 8r x 6r x 8r box, from the Couette profile, to strain 6, with the default
// solid numerics (MTHINC phi, B of the 0.5 <= phi < 0.9 band from the core
// and of the outer band from the solid side, det B projected, B's positive
// fallback). The old numerics (WENO5 phi, B by its
// own equation everywhere, no projection, no fallback) are run alongside as
// the control that the checks can fail.
//
// Bounds and their source. det B in phi > 0.5 cells stays in [0.97, 1.03]
// before the projection (the bound). The intrinsic viscosity [mu]
// averaged over strain [2, 4) and [4, 6) differs by less than 3%: the damped
// shape oscillation (period about 12 strain units) moves it by about 1%
// between such windows. Measured: default numerics [mu] 2.5955 and 2.5640
// (-1.2%), det B in [0.9996, 1.0005], phi < 0.1 cells 2.2% of the elastic
// shear stress and of the solid volume (THINC with b_solid_phi 0.5, the
// default until round 15: [mu] 2.768 and 2.784, det B in [0.9989, 1.0021],
// 3.6%); old numerics [mu] 3.67 and 4.75 (+29%), det B in [0.86, 6.1],
// phi < 0.1 cells 44%.
#include <gtest/gtest.h>

#include "diagnostics.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
struct TankTreading {
  double mu_early, mu_late, detb_min, detb_max, lowphi_max, shed_max;
};

TankTreading tank_tread(const std::vector<std::string>& numerics) {
  std::vector<std::string> keys = {"grid.lx=8.0",
                                   "grid.ly=6.0",
                                   "grid.lz=8.0",
                                   "walls.velocity=3.0",
                                   "fluid.mu=10.0",
                                   "particles.radius=1.0",
                                   "particles.count=1",
                                   "particles.placement=centre",
                                   "particles.capillary=0.2",
                                   "initial.type=couette",
                                   "time.viscous=implicit"};
  keys.insert(keys.end(), numerics.begin(), numerics.end());
  Config c = couette_case(32, 24, 32, keys);
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  Diagnostics d(s);
  const double phi = 4 * M_PI / 3 / (8.0 * 6.0 * 8.0);
  TankTreading r{0, 0, 1, 1, 0, 0};
  double sum[2] = {0, 0};
  int n[2] = {0, 0};
  while (s.time < 6.0) {
    s.advance(std::min(s.stable_dt(), 6.0 - s.time + 1e-12));
    if (s.step % 5) continue;
    const FlowScalars f = d.scalars();
    r.detb_min = std::min(r.detb_min, f.detb_raw_min);
    r.detb_max = std::max(r.detb_max, f.detb_raw_max);
    if (s.time >= 1) r.lowphi_max = std::max(r.lowphi_max, f.elastic_share_lowphi);
    r.shed_max = std::max(r.shed_max, f.solid_share_lowphi);
    if (s.time >= 2) {
      const int w = s.time < 4 ? 0 : 1;
      sum[w] += (f.mu_eff - 1) / phi, ++n[w];
    }
  }
  r.mu_early = sum[0] / n[0];
  r.mu_late = sum[1] / n[1];
  if (world_rank() == 0)
    std::printf(
        "  [mu] %.4f (strain 2-4)  %.4f (4-6)  det B in [%.4f, %.4f]  phi < 0.1 share: elastic %.3f, volume "
        "%.4f\n",
        r.mu_early, r.mu_late, r.detb_min, r.detb_max, r.lowphi_max, r.shed_max);
  return r;
}
}  // namespace

TEST(TankTreading, SolidStaysPhysicalAndViscosityStationary) {
  const TankTreading a = tank_tread({});
  EXPECT_GE(a.detb_min, 0.97);
  EXPECT_LE(a.detb_max, 1.03);
  EXPECT_LT(std::abs(a.mu_late / a.mu_early - 1), 0.03);
  EXPECT_LT(a.lowphi_max, 0.05);
  // the solid itself stays in the particle: cells with phi < 0.1 hold less
  // of its volume than the 5% bound on their share of the stress
  // (measured 2.2%, a sphere's sampled band 0.4%; WENO5's smearing 7.4%)
  EXPECT_LT(a.shed_max, 0.05);
  // the control: the old numerics break every bound in the same run
  const TankTreading old = tank_tread({"particles.phi_scheme=weno5", "particles.b_extension=false",
                                       "particles.unimodular_b=false", "particles.b_fallback=false"});
  EXPECT_GT(std::max(1 - old.detb_min, old.detb_max - 1), 0.03);
  EXPECT_GT(std::abs(old.mu_late / old.mu_early - 1), 0.03);
  EXPECT_GT(old.lowphi_max, 0.05);
  EXPECT_GT(old.shed_max, 0.05);
}
