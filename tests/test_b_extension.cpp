// B's extension from the solid side (kernels/solid_extension.hpp) with the
// inner band of particles.b_solid_phi: cells with 0.5 <= phi < b_solid_phi
// take B from the core (phi >= b_solid_phi) and keep their own B where no
// core cell is within two cells; the outer band (phi < 0.5) then reads them.
// A plane interface along x, uniform in y and z, on one rank.
#include <gtest/gtest.h>

#include <cstdlib>

#include "../kernels/near_mask.hpp"
#include "../kernels/solid_extension.hpp"
#include "solid_util.hpp"

using namespace softflow;

namespace {

constexpr int ng = Grid::ng;
// phi along x (storage index i): the core, then 0.95, 0.7, 0.3, fluid, and
// one isolated 0.7 cell far from the core
constexpr int i_core_end = ng + 5, i_inner = ng + 6, i_outer = ng + 7, i_fluid = ng + 8, i_lone = ng + 13;
// B of the core (det 1), and distinct, wrong values in the band cells
constexpr Real b_core[6] = {1.5, 0.4, 0.1, 0.9, 0.05, 1.0 / 1.2};
constexpr Real b_inner[6] = {2.0, 0.9, 0.0, 0.7, 0.0, 1.0};
constexpr Real b_outer[6] = {3.0, 1.5, 0.0, 0.6, 0.0, 1.0};

Grid plane_grid() {
  Grid g;
  g.nx = g.nxl = 16;
  g.ny = 6;
  g.nz = g.nzl = 6;
  g.lx = g.ly = g.lz = 1;
  g.dx = g.dy = g.dz = 1.0 / 16;
  return g;
}

// the three B values, captured by value in the kernel (device-safe)
struct PlaneB {
  Real core[6], inner[6], outer[6];
};

void set_plane(const Grid& g, const SolidFields& f) {
  const SolidViews q(f);
  PlaneB pb;
  for (int m = 0; m < 6; ++m) pb.core[m] = b_core[m], pb.inner[m] = b_inner[m], pb.outer[m] = b_outer[m];
  par_for(
      "test_extension_plane", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        Real p = 0, b[6] = {1, 0, 0, 1, 0, 1};
        if (i <= i_core_end) {
          p = i == i_core_end ? 0.95 : 1;
          for (int m = 0; m < 6; ++m) b[m] = pb.core[m];
        }
        if (i == i_inner || i == i_lone) {
          p = 0.7;
          for (int m = 0; m < 6; ++m) b[m] = pb.inner[m];
        }
        if (i == i_outer) {
          p = 0.3;
          for (int m = 0; m < 6; ++m) b[m] = pb.outer[m];
        }
        q.phi(i, j, k) = p;
        for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = b[m];
      });
}

// B at (i, mid y, mid z) on the host
std::vector<Real> b_at(const SolidFields& f, int i) {
  std::vector<Real> b(6);
  for (int m = 0; m < 6; ++m) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), f.B(m));
    b[m] = h(i, ng + 3, ng + 3);
  }
  return b;
}

void expect_b(const std::vector<Real>& b, const Real* want, const char* what) {
  for (int m = 0; m < 6; ++m) EXPECT_NEAR(b[m], want[m], 1e-14) << what << ", component " << m;
}

// one extension pass over the interior, as SolidPhase::constrain_b runs it;
// with log_mean the sources' logs first
void extend(const Grid& g, const SolidFields& f, ExtensionBand band, bool log_mean = false) {
  Field3 a("a", g.sx(), g.sy(), g.sz()), b("b", g.sx(), g.sy(), g.sz());
  if (log_mean) {
    band.logs = SolidFields(g, "logs");
    const Range3 sources = grown(g.interior(), 2, g.all());
    mark_near_below(f.phi(), band.source_min, 2, sources, a, b, a);
    log_core_b(f, sources, band.source_min, a, band.logs);
  }
  mark_near(f.phi(), band.source_min, 2, g.interior(), a, b, a);
  extend_b_from_solid(f, g.interior(), a, band);
}

}  // namespace

TEST(BExtension, InnerBandTakesTheCoresBAndKeepsItsOwnOutOfReach) {
  const Grid g = plane_grid();
  SolidFields f(g, "test");
  set_plane(g, f);
  extend(g, f, ExtensionBand{phi_solid, 0.9, true});
  expect_b(b_at(f, i_inner), b_core, "the 0.7 cell beside the core");
  expect_b(b_at(f, i_lone), b_inner, "the lone 0.7 cell (no core within two cells)");
  expect_b(b_at(f, i_outer), b_outer, "the 0.3 cell (not in the inner band)");
  expect_b(b_at(f, i_core_end), b_core, "the 0.95 cell (a source)");
  // the outer band then reads the inner band's new B: the core's everywhere
  extend(g, f, ExtensionBand{});
  expect_b(b_at(f, i_outer), b_core, "the 0.3 cell after the outer pass");
  expect_b(b_at(f, i_fluid), b_core, "the fluid cell beside the band");
}

TEST(BExtension, DefaultBandMixesTheInterfaceCellsOwnB) {
  // what the inner band changes: with sources from phi >= 0.5 (the default),
  // the 0.3 cell averages the core's B with the 0.7 cell's own
  const Grid g = plane_grid();
  SolidFields f(g, "test");
  set_plane(g, f);
  extend(g, f, ExtensionBand{});
  const std::vector<Real> b = b_at(f, i_outer);
  EXPECT_GT(std::abs(b[1] - b_core[1]), 0.05) << "B_xy of the 0.3 cell: " << b[1];
  EXPECT_GT(b[1], b_core[1]);
  EXPECT_LT(b[1], b_inner[1]);
  expect_b(b_at(f, i_lone), b_inner, "the lone 0.7 cell (a source, not written)");
}

namespace {
// det 1 stretches R(theta) diag(l, 1 / l, 1) R(theta)^T about z, theta
// alternating with j: the core's B has two orientations
void set_two_orientations(const Grid& g, const SolidFields& f, double l, double theta) {
  const SolidViews q(f);
  par_for(
      "test_extension_two_orientations", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        const bool core = i <= i_core_end;
        q.phi(i, j, k) = core ? 1.0 : (i == i_inner ? 0.7 : 0.0);
        Real b[6];
        test::stretch_about_z(l, (j % 2 == 0) ? theta : -theta, b);
        for (int m = 0; m < 6; ++m)
          q.field(1 + m)(i, j, k) = (core || i == i_inner) ? b[m] : (m % 3 == 0 ? 1 : 0);
      });
}
}  // namespace

TEST(BExtension, LogEuclideanMeanKeepsDetOneWhereThePlainMeanSwells) {
  const Grid g = plane_grid();
  SolidFields f(g, "test");
  // l = 4, +-0.6 rad: the plain mean of the two, equally weighted, has det 4.05
  set_two_orientations(g, f, 4.0, 0.6);
  extend(g, f, ExtensionBand{phi_solid, 0.9, true});
  const double plain = test::det6(b_at(f, i_inner).data());
  EXPECT_GT(plain, 1.3) << "the plain mean's det";
  set_two_orientations(g, f, 4.0, 0.6);
  extend(g, f, ExtensionBand{phi_solid, 0.9, true}, true);
  const std::vector<Real> b = b_at(f, i_inner);
  EXPECT_NEAR(test::det6(b.data()), 1.0, 1e-12) << "the log-Euclidean mean's det";
  EXPECT_GT(b[0], 1.0) << "still stretched along x";
}

namespace {

// The two tests' fields below, set outside their TEST bodies: nvcc forbids
// extended (KOKKOS_LAMBDA) lambdas in gtest's private TestBody.
// phi = 0.95 everywhere but 0.3 in cell (ic, jc, kc)
void set_one_low_cell(const Grid& g, const Field3& phi, int ic, int jc, int kc) {
  par_for(
      "test_near_below_phi", g.all(),
      KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) = (i == ic && j == jc && k == kc) ? 0.3 : 0.95; });
}

// B_xy = 5 in the core cell beside the 0.7 cell: B_xy^2 > B_xx B_yy there
void break_one_source(const Grid& g, const SolidFields& f) {
  const SolidViews q(f);
  par_for(
      "test_extension_broken_source", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        if (i == i_core_end && j == ng + 3 && k == ng + 3) q.b1(i, j, k) = 5;
      });
}

}  // namespace

TEST(BExtension, NearBelowMarksTheBlockOfALowCellAtTheStoragesEdge) {
  // one cell below the threshold in a storage corner (a ghost cell): the
  // block's reads are clamped there, so exactly the cells within two of it
  // are marked, and the passes read nothing outside the storage
  const Grid g = plane_grid();
  Field3 phi("phi", g.sx(), g.sy(), g.sz()), a("a", g.sx(), g.sy(), g.sz()), b("b", g.sx(), g.sy(), g.sz());
  const int ic = 0, jc = 2, kc = g.sz() - 1;
  set_one_low_cell(g, phi, ic, jc, kc);
  mark_near_below(phi, 0.9, 2, g.all(), a, b, a);
  auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), a);
  int wrong = 0, marked = 0;
  for (int k = 0; k < g.sz(); ++k)
    for (int j = 0; j < g.sy(); ++j)
      for (int i = 0; i < g.sx(); ++i) {
        const bool want = std::abs(i - ic) <= 2 && std::abs(j - jc) <= 2 && std::abs(k - kc) <= 2;
        wrong += (h(i, j, k) == 1) != want;
        marked += h(i, j, k) == 1;
      }
  EXPECT_EQ(wrong, 0);
  EXPECT_EQ(marked, 3 * 5 * 3);  // the block cut by the storage's edges
}

TEST(BExtension, LogMeanSkipsASourceThatIsNotPositiveDefinite) {
  // one core cell beside the 0.7 cell holds a B with a negative eigenvalue:
  // its log is not taken, and the band's mean is that of the other sources
  const Grid g = plane_grid();
  SolidFields f(g, "test");
  set_plane(g, f);
  break_one_source(g, f);
  extend(g, f, ExtensionBand{phi_solid, 0.9, true}, true);
  const std::vector<Real> b = b_at(f, i_inner);
  // every other source holds the core's B: its log mean is the core's B
  expect_b(b, b_core, "the 0.7 cell beside the broken source");
}
