// A single neo-Hookean sphere in Couette flow at small Ca deforms into an
// ellipsoid with Taylor parameter T = (5/4) Ca at leading order.
//
// Theory: at small Ca the particle's strain is small and the elastic stress
// 2 G eps inside it balances the stress a rigid sphere would carry, 5 mu E
// (the stresslet (20/3) pi mu a^3 E spread over the volume), so
// eps = (5/2) (mu / G) E. In simple shear E's principal values are +-gamma/2,
// so the principal stretches are 1 +- (5/4) Ca and T = (5/4) Ca (Roscoe 1967;
// Gao, Hu & Castaneda, JFM 2011, eq. for the small-Ca limit). The material
// rotation (tank-treading) changes T only at O(Ca^2).
//
// The run differs from the theory's assumptions: walls at 3 radii (a
// confinement 2r / 2h = 1/3, which raises the deformation: the confinement
// correction of Shapira & Haber (1990) for drops is about +20% here), a
// particle Reynolds number of 1 instead of 0, and 4 points per radius with a
// diffuse interface, which adds an offset of about 0.02 to T (seen as the
// ratio falling from 1.32 at Ca = 0.05 to 1.19 at Ca = 0.1 when first
// measured). The test therefore asks for T / ((5/4) Ca) in [0.9, 1.4] and for
// T to grow with Ca at a slope within 20% of linear.
#include <gtest/gtest.h>

#include "particle_tracker.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
double taylor_at(double ca) {
  Config c = couette_case(32, 24, 32,
                          {"grid.lx=8.0", "grid.ly=6.0", "grid.lz=8.0", "walls.velocity=3.0", "fluid.mu=1.0",
                           "particles.radius=1.0", "particles.count=1", "particles.placement=centre",
                           "particles.capillary=" + std::to_string(ca)});
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  ParticleTracker tr(s, ParticleTracker::from_spheres(s.solid()->spheres(), c.particles));
  double sum = 0;
  int n = 0;
  const double end = 3.0;
  while (s.time < end) {
    s.advance(std::min(s.stable_dt(), end - s.time + 1e-12));
    tr.update();
    if (s.time > 2.0) sum += tr.shapes()[0].taylor, ++n;  // steady after ~2 strain units
  }
  const double T = sum / n;
  if (world_rank() == 0)
    std::printf("  Ca = %.3f: T = %.4f, theory (5/4) Ca = %.4f, ratio %.3f, inclination %.1f deg\n", ca, T,
                1.25 * ca, T / (1.25 * ca), tr.shapes()[0].angle * 180 / M_PI);
  return T;
}
}  // namespace

TEST(Taylor, SmallCaDeformationMatchesTheory) {
  const double t1 = taylor_at(0.05), t2 = taylor_at(0.1);
  for (double r : {t1 / (1.25 * 0.05), t2 / (1.25 * 0.1)}) {
    EXPECT_GT(r, 0.9);
    EXPECT_LT(r, 1.4);
  }
  EXPECT_NEAR((t2 - t1) / (1.25 * 0.05), 1.0, 0.2);  // the slope dT/dCa against 5/4
}
