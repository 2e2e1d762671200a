// The return of lost solid (kernels/solid_debris.hpp): a sphere with a
// tanh edge, a wisp of solid far from it (no phi >= 1/2 within two cells),
// and a small piece with a core above 1/2. The wisp goes back to the
// interface; the sphere and the piece stay; the volume is conserved and phi
// stays in [0, 1]. One rank.
#include <gtest/gtest.h>

#include <cmath>

#include "../kernels/near_mask.hpp"
#include "../kernels/solid_debris.hpp"
#include "solid_util.hpp"

using namespace softflow;

namespace {

constexpr int ng = Grid::ng, n = 24;
// storage indices: the sphere about (8, 12, 12) + ng, radius 5 cells; the
// wisp along x at y = z = 12 (7 cells beyond the sphere's edge); the piece
// about (19, 4, 4)
constexpr int wisp_lo = ng + 20, wisp_hi = ng + 21, wisp_jk = ng + 12;
constexpr int piece_i = ng + 19, piece_jk = ng + 4;

Grid box() {
  Grid g;
  g.nx = g.nxl = g.ny = g.nz = g.nzl = n;
  g.lx = g.ly = g.lz = 1;
  g.dx = g.dy = g.dz = 1.0 / n;
  return g;
}

// phi and a det-1 stretched B inside every solid cell; `wisp`: with the wisp
void set_scene(const Grid& g, const SolidFields& f, bool wisp) {
  const SolidViews q(f);
  par_for(
      "test_debris_scene", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        const Real x = i - ng - 8, y = j - ng - 12, z = k - ng - 12;
        Real p = Real(0.5) * (1 - Kokkos::tanh(Real(3.5) * (Kokkos::sqrt(x * x + y * y + z * z) - 5)));
        if (p < Real(1e-10)) p = 0;
        const int di = i - piece_i, dj = j - piece_jk, dk = k - piece_jk;
        if (di == 0 && dj == 0 && dk == 0)
          p = 0.6;
        else if (di * di + dj * dj + dk * dk == 1)
          p = 0.1;
        if (wisp && j == wisp_jk && k == wisp_jk && i >= wisp_lo && i <= wisp_hi) p = 0.04;
        Real b[6] = {1, 0, 0, 1, 0, 1};
        if (p > 0) test::stretch_about_z(1.8, 0.3, b);
        q.phi(i, j, k) = p;
        for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = b[m];
      });
}

struct Scene {
  Grid g = box();
  SolidFields f{g, "debris"};
  Field3 near{"debris_near", g.sx(), g.sy(), g.sz()}, sx{"debris_sx", g.sx(), g.sy(), g.sz()},
      sy{"debris_sy", g.sx(), g.sy(), g.sz()};
  Real sums[3];
  explicit Scene(bool wisp) {
    set_scene(g, f, wisp);
    block_max(f.phi(), 2, g.interior(), sx, sy, near);
    debris_sums(f.phi(), near, g.interior(), sums);
  }
};

double volume(const Field3& phi, const Range3& r) {
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), phi);
  double s = 0;
  for (int k = r.kb; k < r.ke; ++k)
    for (int j = r.jb; j < r.je; ++j)
      for (int i = r.ib; i < r.ie; ++i) s += h(i, j, k);
  return s;
}

}  // namespace

// a sphere alone: only its far tail counts as debris (below 3e-8 a cell beyond
// 2.5 cells of the 1/2 level), not its interface band
TEST(SolidDebris, SphereAloneIsNotDebris) {
  if (test::world_size() > 1) GTEST_SKIP() << "one rank";
  Scene s(false);
  EXPECT_LT(s.sums[0] / s.sums[2], 1e-6);
}

TEST(SolidDebris, WispReturnsToTheInterface) {
  if (test::world_size() > 1) GTEST_SKIP() << "one rank";
  Scene s(true);
  const Range3 in = s.g.interior();
  const double before = volume(s.f.phi(), in);
  // the wisp's 2 cells of 0.04 (and the sphere's far tail, < 1e-6 of it)
  EXPECT_NEAR(s.sums[0], 0.08, 1e-6 * s.sums[2]);
  auto old_phi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.f.phi());
  return_debris(s.f, s.near, in, s.sums);
  const double after = volume(s.f.phi(), in);
  EXPECT_NEAR(after, before, 1e-13 * before) << "volume";
  auto phi = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.f.phi());
  auto bxx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.f.B(0));
  auto bxy = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), s.f.B(1));
  for (int i = wisp_lo; i <= wisp_hi; ++i) {
    EXPECT_EQ(phi(i, wisp_jk, wisp_jk), 0) << "wisp cell " << i;
    EXPECT_EQ(bxx(i, wisp_jk, wisp_jk), 1) << "wisp cell " << i;
    EXPECT_EQ(bxy(i, wisp_jk, wisp_jk), 0) << "wisp cell " << i;
  }
  // the piece keeps its core and its edge (within two cells of the core)
  EXPECT_GE(phi(piece_i, piece_jk, piece_jk), 0.6);
  EXPECT_GE(phi(piece_i + 1, piece_jk, piece_jk), 0.1);
  // phi in [0, 1]; the cells that stay only gain (the return adds a c (1 - c))
  int lost = 0, out_of_range = 0;
  for (int k = in.kb; k < in.ke; ++k)
    for (int j = in.jb; j < in.je; ++j)
      for (int i = in.ib; i < in.ie; ++i) {
        out_of_range += phi(i, j, k) < 0 || phi(i, j, k) > 1;
        const bool wisp = j == wisp_jk && k == wisp_jk && i >= wisp_lo && i <= wisp_hi;
        lost += !wisp && old_phi(i, j, k) > 1e-6 && phi(i, j, k) < old_phi(i, j, k);
      }
  EXPECT_EQ(out_of_range, 0);
  EXPECT_EQ(lost, 0);
}
