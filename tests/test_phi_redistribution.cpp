// Where phi's clipped volume goes (kernels/phi_local_redistribution.hpp): an
// overshoot at one interface cell of one of two spheres is given back to the
// interface cells around it ("local"), not to both spheres ("global").
#include <gtest/gtest.h>

#include "diagnostics.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
// Device loops outside the TEST body (nvcc). Two spheres of radius r about
// (0.5, 0, 0.5) and (1.5, 0, 1.5), phi from 4^3 sub-samples per cell.
void fill_two_spheres(const Grid& g, const Field3& phi, double r) {
  par_for(
      "test_two_spheres", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        int in = 0;
        for (int a = 0; a < 4; ++a)
          for (int b = 0; b < 4; ++b)
            for (int e = 0; e < 4; ++e) {
              const double x = g.xc(i) + g.dx * ((a + 0.5) / 4 - 0.5),
                           y = g.yc(j) + g.dy * ((b + 0.5) / 4 - 0.5),
                           z = g.zc(k) + g.dz * ((e + 0.5) / 4 - 0.5);
              for (double c : {0.5, 1.5}) in += (x - c) * (x - c) + y * y + (z - c) * (z - c) < r * r;
            }
        phi(i, j, k) = in / 64.0;
      });
}
// adds `by` to phi in the cell that holds (x, y, z) (on whichever rank has it)
void add_at(const Grid& g, const Field3& phi, double x, double y, double z, double by) {
  par_for(
      "test_add_at", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        if (Kokkos::fabs(g.xc(i) - x) <= g.dx / 2 && Kokkos::fabs(g.yc(j) - y) <= g.dy / 2 &&
            Kokkos::fabs(g.zc(k) - z) <= g.dz / 2)
          phi(i, j, k) += by;
      });
}
struct Change {
  double near = 0, far = 0, min = 1,
         max = 0;  // largest |change| within / beyond one cell of (x0, z0); phi's range
};
Change change(const Grid& g, const Field3& phi, const Field3& before, double x0, double y0, double z0) {
  Change c;
  for (int near = 0; near < 2; ++near)
    par_reduce(
        "test_change", g.interior(),
        KOKKOS_LAMBDA(int i, int j, int k, double& m) {
          const bool n = Kokkos::fabs(g.xc(i) - x0) < 1.6 * g.dx && Kokkos::fabs(g.yc(j) - y0) < 1.6 * g.dy &&
                         Kokkos::fabs(g.zc(k) - z0) < 1.6 * g.dz;
          if (n == bool(near)) m = Kokkos::fmax(m, Kokkos::fabs(phi(i, j, k) - before(i, j, k)));
        },
        Kokkos::Max<double>(near ? c.near : c.far));
  par_reduce(
      "test_phi_max", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& m) { m = Kokkos::fmax(m, phi(i, j, k)); },
      Kokkos::Max<double>(c.max));
  par_reduce(
      "test_phi_min", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& m) { m = Kokkos::fmin(m, phi(i, j, k)); },
      Kokkos::Min<double>(c.min));
  c.near = global_max(c.near), c.far = global_max(c.far), c.max = global_max(c.max);
  c.min = -global_max(-c.min);
  return c;
}
}  // namespace

// An interface cell of the first sphere (phi 0.75, on its surface at
// x = 0.5 + r) pushed to 1.35: clipped by 0.35, far more than the
// transport's overshoots, so that a leak anywhere shows. Local: the volume is
// conserved to round-off (1e-13 of it, the sum's rounding), phi stays in
// [0, 1], and no cell more than one cell from the overshoot changes at all.
// Global: the same volume and bounds, but every interface cell of both
// spheres changes.
TEST(Solid, ClippedVolumeGoesBackNextToWhereItWasClipped) {
  const double r = 0.3, x0 = 0.5 + r, y0 = 0.0, z0 = 0.5;
  for (const char* mode : {"local", "global"}) {
    Config c = couette_case(32, 32, 32,
                            solid_keys({"walls.velocity=0.0", "grid.lx=2.0", "grid.ly=2.0", "grid.lz=2.0",
                                        std::string("particles.phi_redistribution=\"") + mode + "\""}));
    FlowSolver s(c, MPI_COMM_WORLD);
    s.initialize();
    const Grid g = s.grid();
    const Field3 phi = s.solid()->fields().phi();
    fill_two_spheres(g, phi, r);
    add_at(g, phi, x0, y0, z0, 0.6);
    s.solid()->fill_ghosts();
    const double v0 = Diagnostics(s).scalars().solid_volume;
    Field3 before("before", g.sx(), g.sy(), g.sz());
    Kokkos::deep_copy(before, phi);
    s.solid()->keep_phi_bounded();
    s.solid()->fill_ghosts();
    const double v1 = Diagnostics(s).scalars().solid_volume;
    const Change d = change(g, phi, before, x0, y0, z0);
    if (world_rank() == 0)
      std::printf(
          "  %s: volume change %.1e, phi in [%.3g, %.17g], largest change near %.3g, beyond one cell %.3g\n",
          mode, v1 / v0 - 1, d.min, d.max, d.near, d.far);
    EXPECT_NEAR(v1, v0, 1e-13 * v0) << mode;
    EXPECT_GE(d.min, 0.0) << mode;
    EXPECT_LE(d.max, 1.0) << mode;
    EXPECT_GT(d.near, 0.2) << mode << ": the overshoot is clipped";
    if (std::string(mode) == "local")
      EXPECT_EQ(d.far, 0.0) << "the clipped volume went beyond the neighbourhood";
    else
      EXPECT_GT(d.far, 1e-4) << "global: every interface cell takes a share";
  }
}
