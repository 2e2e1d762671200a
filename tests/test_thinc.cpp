// THINC (kernels/thinc.hpp): the point-wise step, and phi's transport with
// it against WENO5 on a square wave (1-D) and LeVeque's deformation (3-D,
// in test_solid.cpp).
#include <gtest/gtest.h>

#include "../kernels/thinc.hpp"
#include "diagnostics.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {
// the tanh step of cell (qm, qc, qp) at X in [0, 1], from its two face values:
// the step's centre X0 follows from A = -tanh(beta X0)
double step_at(double qm, double qc, double qp, double beta, double X) {
  const Thinc t = make_thinc(beta);
  const ThincStep s = thinc_step(qm, qc, qp);
  const double x0 = std::atanh(-thinc_A(s, t)) / beta;
  return s.qmin + s.dq / 2 * (1 + s.theta * std::tanh(beta * (X - x0)));
}
}  // namespace

TEST(Thinc, StepAveragesToTheCellValueAndStaysInItsNeighboursRange) {
  for (double beta : {1.0, 2.0, 3.5})
    for (double qc : {0.01, 0.2, 0.5, 0.8, 0.99})
      for (int dir : {+1, -1}) {
        const double qm = dir > 0 ? 0.0 : 1.0, qp = dir > 0 ? 1.0 : 0.0;
        // midpoint rule on 20000 points: exact to ~1e-9 for these steps
        double avg = 0;
        const int n = 20000;
        for (int s = 0; s < n; ++s) avg += step_at(qm, qc, qp, beta, (s + 0.5) / n) / n;
        EXPECT_NEAR(avg, qc, 1e-8) << "beta " << beta << " qc " << qc;
        const double r = thinc_right(qm, qc, qp, make_thinc(beta)),
                     l = thinc_left(qm, qc, qp, make_thinc(beta));
        EXPECT_NEAR(r, step_at(qm, qc, qp, beta, 1.0), 1e-12);
        EXPECT_NEAR(l, step_at(qm, qc, qp, beta, 0.0), 1e-12);
        EXPECT_GE(std::min(l, r), 0.0);
        EXPECT_LE(std::max(l, r), 1.0);
        // the face towards the larger neighbour carries more than the cell
        EXPECT_GT(dir > 0 ? r : l, qc);
      }
}

TEST(Thinc, NonInterfaceCellsGiveTheirOwnValue) {
  const Thinc t = make_thinc(2.0);
  EXPECT_EQ(thinc_right(0.0, 0.0, 0.0, t), 0.0);
  EXPECT_EQ(thinc_right(1.0, 1.0, 1.0, t), 1.0);
  EXPECT_EQ(thinc_right(0.0, 0.7, 0.3, t), 0.7);  // an extremum: first-order upwind
  // the face value from the right (vel < 0) mirrors the one from the left
  // (Courant number 0: the point value at the face)
  EXPECT_DOUBLE_EQ(thinc_face(-1, 0.9, 0.6, 0.3, 0.0, t, 0.0), thinc_left(0.6, 0.3, 0.0, t));
  EXPECT_DOUBLE_EQ(thinc_face(+1, 0.0, 0.3, 0.6, 0.9, t, 0.0), thinc_right(0.0, 0.3, 0.6, t));
  EXPECT_DOUBLE_EQ(thinc_face(-1, 0.9, 0.6, 0.3, 0.0, t, 0.3), thinc_face(+1, 0.0, 0.3, 0.6, 0.9, t, 0.3));
}

TEST(Thinc, SweptMeanIsTheStepsMeanOverTheSweptPartAndKeepsAnEulerStepBounded) {
  for (double beta : {1.0, 2.0, 3.5, 8.0})
    for (double qc : {1e-9, 0.01, 0.2, 0.5, 0.8, 0.99, 1 - 1e-9})
      for (int dir : {+1, -1})
        for (double nu : {1e-6, 0.05, 0.4, 1.0}) {
          const double qm = dir > 0 ? 0.0 : 1.0, qp = dir > 0 ? 1.0 : 0.0;
          const Thinc t = make_thinc(beta);
          const double f = thinc_right_swept(qm, qc, qp, t, nu);
          // against the midpoint rule over [1 - nu, 1] on 20000 points (the
          // closed form avoids X0, which the midpoint rule needs; skipped where
          // atanh(-A) is not representable)
          const ThincStep st = thinc_step(qm, qc, qp);
          if (std::fabs(thinc_A(st, t)) < 1 - 1e-6) {
            double avg = 0;
            const int n = 20000;
            for (int s = 0; s < n; ++s) avg += step_at(qm, qc, qp, beta, 1 - nu + nu * (s + 0.5) / n) / n;
            EXPECT_NEAR(f, avg, 1e-8) << "beta " << beta << " qc " << qc << " nu " << nu;
          }
          // One explicit step at Courant number nu with the upwind cell full
          // (falling step) or empty (rising step): the cell's new value is
          // qc + nu (1 - f) or qc - nu f, and stays in [0, 1] because the
          // swept part holds at most the cell's emptiness or its volume. To
          // round-off: near nu = 1 in a nearly full or empty cell the log's
          // argument falls to ~e^{-beta}, which scales its rounding by ~e^beta.
          const double tol = 1e-15 * std::exp(beta);
          if (dir < 0)
            EXPECT_LE(qc + nu * (1 - f), 1 + tol) << "beta " << beta << " qc " << qc << " nu " << nu;
          if (dir > 0) EXPECT_GE(qc - nu * f, -tol) << "beta " << beta << " qc " << qc << " nu " << nu;
        }
  // tends to the point value (a different formula) as nu -> 0
  const Thinc t = make_thinc(3.5);
  EXPECT_NEAR(thinc_right_swept(0, 0.3, 1, t, 1e-10), thinc_right(0, 0.3, 1, t), 1e-9);
  EXPECT_NEAR(thinc_right_swept(0, 0.3, 1, t, 0.0), thinc_right(0, 0.3, 1, t), 1e-14);
}

namespace {
struct UniformX {
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double, double, double, double) const { return {1.0, 0.0, 0.0}; }
};
// cell averages of the square wave 1 on [0.25, 0.75) shifted by s, periodic in [0, 1)
void fill_square(const Grid& g, const Field3& phi, double s) {
  par_for(
      "test_fill_square", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const double a = g.xc(i) - g.dx / 2 - s, b = a + g.dx;
        double in = 0;
        // overlap of [a, b) with the periodic copies of [0.25, 0.75)
        for (int p = -2; p <= 2; ++p) {
          const double lo = Kokkos::fmax(a, 0.25 + p), hi = Kokkos::fmin(b, 0.75 + p);
          in += Kokkos::fmax(0.0, hi - lo);
        }
        phi(i, j, k) = in / g.dx;
      });
}
struct SquareWaveResult {
  double l1, volume_drift, phi_min, phi_max, band;  // band: interface cells per interface per x line
};
// the square wave carried once through the periodic box (CFL 0.4)
SquareWaveResult advect_square_wave(int n, const std::string& scheme) {
  Config c = couette_case(n, 4, 4,
                          solid_keys({"walls.velocity=0.0", "grid.lx=1.0", "grid.ly=1.0", "grid.lz=1.0",
                                      "particles.phi_scheme=" + scheme}));
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  const Grid g = s.grid();
  auto phi = s.solid()->fields().phi();
  fill_square(g, phi, 0);
  s.solid()->fill_ghosts();
  Field3 exact("exact", g.sx(), g.sy(), g.sz());
  fill_square(g, exact, 0);  // one period later: the same
  const double v0 = Diagnostics(s).scalars().solid_volume;
  const int steps = int(std::lround(n / 0.4));
  for (int k = 0; k < steps; ++k) transport_step(s, UniformX{}, 1.0 / steps);
  const FlowScalars f = Diagnostics(s).scalars();
  double l1 = 0;
  par_reduce(
      "test_l1_square", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) { a += Kokkos::fabs(phi(i, j, k) - exact(i, j, k)); },
      Kokkos::Sum<double>(l1));
  const double lines = double(g.ny) * g.nz;
  return {global_sum(l1) * g.dx / lines, f.solid_volume / v0 - 1, f.phi_min, f.phi_max,
          interface_cells(g, phi) / lines / 2};
}
}  // namespace

TEST(Thinc, SquareWaveStaysSharpConservedAndBoundedAndConvergesAtFirstOrder) {
  // The L1 error of a discontinuity carried by a scheme that keeps it within a
  // fixed number of cells falls like h (order 1); a scheme that smears it
  // like sqrt(t h) (first-order upwind) gives 1/2, WENO5 about 5/6.
  std::vector<double> hs, thinc, weno;
  for (int n : {32, 64, 128}) {
    const SquareWaveResult t = advect_square_wave(n, "thinc"), w = advect_square_wave(n, "weno5");
    hs.push_back(1.0 / n);
    thinc.push_back(t.l1);
    weno.push_back(w.l1);
    if (world_rank() == 0)
      std::printf("  n = %3d  L1: thinc %.3e weno5 %.3e   band cells: thinc %.2f weno5 %.2f\n", n, t.l1, w.l1,
                  t.band, w.band);
    EXPECT_NEAR(t.volume_drift, 0.0, 1e-12);
    EXPECT_GE(t.phi_min, 0.0);
    EXPECT_LE(t.phi_max, 1.0);
    EXPECT_LE(t.band, 2.0) << "THINC keeps the jump within two cells";
    EXPECT_LT(t.band, w.band) << "and sharper than WENO5";
  }
  const double qt = order(hs, thinc), qw = order(hs, weno);
  if (world_rank() == 0) std::printf("  L1 order: thinc %.2f  weno5 %.2f\n", qt, qw);
  EXPECT_GT(qt, 0.9);
  EXPECT_GT(qt, qw);
}
