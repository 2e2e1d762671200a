// B's admissibility test and first-order positive fallback
// (kernels/solid_b_fallback.hpp, kernels/sym_matrix_log.hpp): the point-wise
// pieces on the host, then a
// jump in B between two strongly stretched states carried across the grid,
// which WENO5 alone turns indefinite, and a resolved B, which must never
// trip the test.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "../kernels/solid_b_fallback.hpp"
#include "../kernels/sym_matrix_log.hpp"
#include "diagnostics.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

TEST(BFallback, AdmissibleMeansPositiveDefiniteAndDetNearOne) {
  double b[6];
  stretch_about_z(20, 0.3, b);
  EXPECT_TRUE(b_admissible(b, 0.02));
  b[1] *= 1.01;  // 1% more shear: det falls to 0.36
  EXPECT_FALSE(b_admissible(b, 0.02));
  EXPECT_TRUE(b_admissible(b, 0.0)) << "still positive definite: admissible without the det test";
  b[1] *= 1.1;  // b_xy^2 > b_xx b_yy: indefinite
  EXPECT_FALSE(b_admissible(b, 0.0));
  const double neg[6] = {-1, 0, 0, -1, 0, 1};  // det 1, not positive definite
  EXPECT_FALSE(b_admissible(neg, 0.0));
}

TEST(BFallback, LogEuclideanMeanOfDetOneMatricesHasDetOne) {
  // a full 3-D stretch: R_z(0.4) R_x(0.9) diag(6, 0.5, 1/3) R^T, det 1
  double b[6];
  {
    const double lam[3] = {6, 0.5, 1.0 / 3}, cz = std::cos(0.4), sz = std::sin(0.4), cx = std::cos(0.9),
                 sx = std::sin(0.9);
    const double Rz[3][3] = {{cz, -sz, 0}, {sz, cz, 0}, {0, 0, 1}},
                 Rx[3][3] = {{1, 0, 0}, {0, cx, -sx}, {0, sx, cx}};
    double R[3][3];
    for (int a = 0; a < 3; ++a)
      for (int c = 0; c < 3; ++c) {
        R[a][c] = 0;
        for (int e = 0; e < 3; ++e) R[a][c] += Rz[a][e] * Rx[e][c];
      }
    for (int a = 0; a < 3; ++a)
      for (int c = a; c < 3; ++c) {
        double v = 0;
        for (int e = 0; e < 3; ++e) v += R[a][e] * lam[e] * R[c][e];
        b[sym_index(a, c)] = v;
      }
  }
  // the eigen-decomposition rebuilds B, with orthonormal vectors
  const SymEigen ev = sym_eigen(b);
  double re[6];
  sym_compose(ev, ev.lam, re);
  for (int m = 0; m < 6; ++m) EXPECT_NEAR(re[m], b[m], 1e-13 * 6);
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) {
      double d = 0;
      for (int e = 0; e < 3; ++e) d += ev.V[e][a] * ev.V[e][c];
      EXPECT_NEAR(d, a == c ? 1.0 : 0.0, 1e-14);
    }
  EXPECT_NEAR(ev.lam[0] * ev.lam[1] * ev.lam[2], 1.0, 1e-13);
  // exp(log B) = B
  double lg[6], back[6];
  sym_log(b, lg);
  sym_exp(lg, back);
  for (int m = 0; m < 6; ++m) EXPECT_NEAR(back[m], b[m], 1e-12 * 6);
  EXPECT_NEAR(lg[0] + lg[3] + lg[5], 0.0, 1e-13) << "tr log B = log det B = 0";
  // mean with a differently stretched det-1 state: the plain mean swells
  // (det > 1), the log-Euclidean one keeps det 1
  double other[6], lo[6], mean_log[6], mean_plain[6], mean[6];
  stretch_about_z(20, -M_PI / 4, other);
  sym_log(other, lo);
  for (int m = 0; m < 6; ++m) {
    mean_log[m] = 0.3 * lg[m] + 0.7 * lo[m];
    mean_plain[m] = 0.3 * b[m] + 0.7 * other[m];
  }
  sym_exp(mean_log, mean);
  EXPECT_NEAR(det6(mean), 1.0, 1e-12);
  EXPECT_GT(det6(mean_plain), 1.5);
  EXPECT_TRUE(b_admissible(mean, 1e-10));
}

TEST(BFallback, CongruenceStretchIsPositiveAndFirstOrderConsistent) {
  Gradient3 g;
  const double L[3][3] = {{0.3, 1.0, -0.2}, {0.1, -0.5, 0.4}, {-0.3, 0.2, 0.2}};  // trace 0
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) g.L[a][c] = L[a][c];
  double b0[6];
  stretch_about_z(5, 0.7, b0);
  // against the explicit source B + tau (L B + B L^T): the difference is
  // tau^2 L B L^T exactly, so it falls 4x per halving of tau
  double prev = 0;
  for (double tau : {0.1, 0.05, 0.025}) {
    double b[6], e[6];
    for (int m = 0; m < 6; ++m) b[m] = b0[m];
    stretch_congruence(g, tau, b);
    const int a_of[6] = {0, 0, 0, 1, 1, 2}, c_of[6] = {0, 1, 2, 1, 2, 2};
    double diff = 0;
    for (int m = 0; m < 6; ++m) {
      e[m] = b0[m] + tau * upper_convected_source(g, b0, a_of[m], c_of[m]);
      diff = std::max(diff, std::abs(b[m] - e[m]));
    }
    if (prev > 0) EXPECT_NEAR(prev / diff, 4.0, 1e-9);
    prev = diff;
    EXPECT_TRUE(b_admissible(b, 0.0));
  }
  // a step far beyond the explicit source's reach (tau |L| ~ 10): the
  // explicit update is indefinite, the congruence stays positive definite
  // with det B = det(I + tau L)^2 det B
  const double tau = 10;
  double b[6], e[6];
  for (int m = 0; m < 6; ++m) b[m] = b0[m];
  stretch_congruence(g, tau, b);
  const int a_of[6] = {0, 0, 0, 1, 1, 2}, c_of[6] = {0, 1, 2, 1, 2, 2};
  for (int m = 0; m < 6; ++m) e[m] = b0[m] + tau * upper_convected_source(g, b0, a_of[m], c_of[m]);
  EXPECT_FALSE(b_admissible(e, 0.0));
  EXPECT_TRUE(b_admissible(b, 0.0));
  double F[3][3];
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) F[a][c] = (a == c) + tau * L[a][c];
  const double dF = F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) -
                    F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
                    F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
  EXPECT_NEAR(det6(b) / (dF * dF * det6(b0)), 1.0, 1e-10);
}

namespace {
// Device loops live outside the TEST bodies (nvcc: no extended lambdas in
// gtest's private TestBody).
// phi = 1 everywhere; B = the det-1 state stretched l:1 along the angle
// theta(x): +-theta0 on either side of x = lx / 2 (jump), or
// theta0 sin(2 pi x / lx) (smooth)
void fill_b(const Grid& g, const SolidFields& f, double l, double theta0, double lx, bool jump) {
  const SolidViews q(f);
  par_for(
      "test_b_fill", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double x = g.xc(i);
        const double th = jump ? (x < lx / 2 ? theta0 : -theta0) : theta0 * Kokkos::sin(2 * M_PI * x / lx);
        double b[6];
        stretch_about_z(l, th, b);
        q.phi(i, j, k) = 1;
        for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = b[m];
      });
}
// the smallest leading minor (b_xx, b_xx b_yy - b_xy^2, det) over the interior:
// positive exactly when every cell's B is positive definite
double min_leading_minor(const Grid& g, const SolidFields& f) {
  const SolidViews q(f);
  double m = 0;
  par_reduce(
      "test_b_minor", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) {
        const double b0 = q.b0(i, j, k), b1 = q.b1(i, j, k), b3 = q.b3(i, j, k);
        const double d = det_sym(b0, b1, q.b2(i, j, k), b3, q.b4(i, j, k), q.b5(i, j, k));
        a = Kokkos::fmin(a, Kokkos::fmin(b0, Kokkos::fmin(b0 * b3 - b1 * b1, d)));
      },
      Kokkos::Min<double>(m));
  return -global_max(-m);
}

struct UniformX {
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double, double, double, double) const { return {1.0, 0.0, 0.0}; }
};

struct CarryResult {
  double min_minor;
  long fallback_cells, cell_stages;
};
// B carried by a uniform u = 1 in x across a quarter of the periodic box:
// 40 steps at Courant number 0.4
CarryResult carry_b(bool fallback, double l, double theta0, bool jump) {
  const double lx = 2.0;
  Config c = couette_case(
      40, 8, 8,
      solid_keys({"walls.velocity=0.0", "grid.lx=2.0", "grid.ly=0.4", "grid.lz=0.4", "particles.radius=0.05",
                  std::string("particles.b_fallback=") + (fallback ? "true" : "false")}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const Grid g = s.grid();
  fill_b(g, s.solid()->fields(), l, theta0, lx, jump);
  s.solid()->fill_ghosts();
  s.solid()->set_region_tracking(false);
  const UniformX uniform;
  const int steps = 40;
  for (int n = 0; n < steps; ++n) transport_step(s, uniform, 0.4 * g.dx);
  long total = s.solid()->take_b_stats().fallback_cells;
  MPI_Allreduce(MPI_IN_PLACE, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
  return {min_leading_minor(g, s.solid()->fields()), total, long(Rk3::stages) * steps * 40 * 8 * 8};
}
}  // namespace

// Two det-1 states stretched 20:1 along +-45 degrees meet at two planes:
// B_xy jumps from +9.975 to -9.975 while B_xx = B_yy = 10.025, so a WENO5
// overshoot of B_xy by 0.5% makes B indefinite. With the fallback, every
// cell stays positive definite.
TEST(BFallback, JumpInBStaysPositiveDefiniteOnlyWithTheFallback) {
  const CarryResult off = carry_b(false, 20, M_PI / 4, true), on = carry_b(true, 20, M_PI / 4, true);
  if (world_rank() == 0)
    std::printf(
        "  jump: smallest leading minor of B %.3e without the fallback, %.3e with it (%ld of %ld "
        "cell-stages fell back)\n",
        off.min_minor, on.min_minor, on.fallback_cells, on.cell_stages);
  EXPECT_LT(off.min_minor, 0.0) << "the test's jump no longer breaks WENO5 alone: it tests nothing";
  EXPECT_EQ(off.fallback_cells, 0);
  EXPECT_GT(on.min_minor, 0.0);
  EXPECT_GT(on.fallback_cells, 0);
}

// A resolved B (stretched 4:1, its axis turning by +-22.5 degrees over the
// box) never trips the test: there the scheme stays WENO5's.
TEST(BFallback, ResolvedBNeverFallsBack) {
  const CarryResult r = carry_b(true, 4, M_PI / 8, false);
  if (world_rank() == 0)
    std::printf("  smooth: smallest leading minor %.3e, %ld cell-stages fell back\n", r.min_minor,
                r.fallback_cells);
  EXPECT_EQ(r.fallback_cells, 0);
  EXPECT_GT(r.min_minor, 0.0);
}
