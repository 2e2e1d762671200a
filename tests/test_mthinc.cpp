// MTHINC (kernels/mthinc.hpp): the plane's fit, its swept means, and its
// reduction to 1-D THINC for a grid-aligned interface. Transport with it:
// test_solid.cpp (LeVeque's deformation, the sphere turning about a tilted
// axis) and test_thinc.cpp (the square wave).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "../kernels/mthinc.hpp"
#include "../kernels/thinc.hpp"

using namespace softflow;

namespace {
// unit normals of many orientations, grid-aligned and diagonal ones included
std::vector<std::array<double, 3>> normals() {
  std::vector<std::array<double, 3>> ns = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1},
                                           {1, 1, 0}, {1, -1, 1}, {-0.2, 0.9, 0.4}};
  for (int a = 0; a < 12; ++a) {
    const double th = 0.31 + 0.53 * a, ph = 0.17 + 0.29 * a;  // spread over the sphere
    ns.push_back({std::sin(ph) * std::cos(th), std::sin(ph) * std::sin(th), std::cos(ph)});
  }
  for (auto& n : ns) {
    const double s = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (double& c : n) c /= s;
  }
  return ns;
}
// H's mean over the box lo..hi by the midpoint rule on m^3 points
double brute_mean(const MthincPlane& p, const MthincExps& x, double beta, const double lo[3],
                  const double hi[3], int m) {
  const double d = mthinc_offset(x, beta);
  double s = 0;
  for (int a = 0; a < m; ++a)
    for (int b = 0; b < m; ++b)
      for (int c = 0; c < m; ++c) {
        const double X = lo[0] + (hi[0] - lo[0]) * (a + 0.5) / m, Y = lo[1] + (hi[1] - lo[1]) * (b + 0.5) / m,
                     Z = lo[2] + (hi[2] - lo[2]) * (c + 0.5) / m;
        s += 0.5 * (1 + std::tanh(beta * (p.n[0] * X + p.n[1] * Y + p.n[2] * Z + d)));
      }
  return s / (double(m) * m * m);
}
}  // namespace

// The fit puts the plane where H's cell mean (by the scheme's quadrature) is
// the cell's value, to the Newton tolerance; the quadrature itself is within
// 5e-3 of the exact mean (2-point Gauss across a step of steepness <= 5 over
// one cell: measured at most 3.5e-3 here, 2.4e-3 at beta = 3.5; 3 points
// gave 2e-4 at 2.6 times the cost, and the same tilted-axis turn in
// test_solid.cpp to 4 digits).
TEST(Mthinc, FitReproducesTheCellValueAndItsQuadratureTheExactMean) {
  const double lo[3] = {-0.5, -0.5, -0.5}, hi[3] = {0.5, 0.5, 0.5};
  double worst = 0;
  for (double beta : {1.0, 2.5, 3.5, 5.0})
    for (const auto& n : normals())
      for (double q : {2e-10, 1e-7, 1e-3, 0.1, 0.5, 0.77, 0.999, 1 - 1e-7, 1 - 2e-10}) {
        const double g[3] = {3 * n[0], 3 * n[1], 3 * n[2]};  // any length: the fit normalises
        MthincExps x;
        const MthincPlane p = mthinc_fit(q, g, beta, x);
        ASSERT_GE(p.dom, 0);
        EXPECT_NEAR(mthinc_box_mean(p, x, q, beta, lo, hi), q, 1e-13) << "beta " << beta << " q " << q;
        for (int a = 0; a < 3; ++a) EXPECT_NEAR(p.n[a], n[a], 1e-15);
        EXPECT_GE(std::fabs(p.n[p.dom]), std::fabs(p.n[(p.dom + 1) % 3]));
        EXPECT_GE(std::fabs(p.n[p.dom]), std::fabs(p.n[(p.dom + 2) % 3]));
        const double e = std::fabs(brute_mean(p, x, beta, lo, hi, 80) - q);
        worst = std::max(worst, e);
        EXPECT_LT(e, 5e-3) << "beta " << beta << " q " << q;
      }
  std::printf("  largest quadrature error of a cell mean: %.1e\n", worst);
}

TEST(Mthinc, CellsWithoutAnInterfaceGiveTheirOwnValue) {
  const double g[3] = {1, 0.5, 0}, flat[3] = {0, 0, 0};
  for (double q : {0.0, 5e-11, 1.0, 1 - 5e-11}) {
    MthincExps x;
    const MthincPlane p = mthinc_fit(q, g, 3.5, x);
    EXPECT_LT(p.dom, 0);
    EXPECT_EQ(mthinc_face_value(p, x, q, 3.5, 0, true, 0.3), q);
  }
  MthincExps x;
  const MthincPlane p = mthinc_fit(0.4, flat, 3.5, x);  // an isolated cell: no normal
  EXPECT_LT(p.dom, 0);
  EXPECT_EQ(mthinc_face_value(p, x, 0.4, 3.5, 1, false, 0.3), 0.4);
}

// A plane across x is 1-D THINC's step along x: same steepness, same cell
// mean, so the same swept means on both faces (THINC's X in [0, 1] is
// MTHINC's X + 1/2).
TEST(Mthinc, AGridAlignedPlaneIsThinc) {
  for (double beta : {1.0, 3.5, 8.0})
    for (double q : {0.01, 0.3, 0.5, 0.9})
      for (double nu : {0.0, 0.05, 0.4, 1.0}) {
        const Thinc t = make_thinc(beta);
        const double rising[3] = {1, 0, 0}, falling[3] = {-1, 0, 0};
        MthincExps xu, xd;
        const MthincPlane up = mthinc_fit(q, rising, beta, xu), down = mthinc_fit(q, falling, beta, xd);
        EXPECT_NEAR(mthinc_face_value(up, xu, q, beta, 0, true, nu), thinc_right_swept(0, q, 1, t, nu), 1e-11)
            << "beta " << beta << " q " << q << " nu " << nu;
        // the left face of a falling step is the right face of the mirrored rising one
        EXPECT_NEAR(mthinc_face_value(down, xd, q, beta, 0, false, nu), thinc_right_swept(0, q, 1, t, nu),
                    1e-11);
      }
}

// Swept means against the midpoint rule, on every face of cells of every
// orientation; and an explicit step at Courant number nu out of one face
// keeps the cell in [0, 1] when the flux runs along the normal's largest
// component (there the slab and the cell share the quadrature nodes across,
// so the slab holds no more than the cell). Across it the slab's own Gauss
// nodes differ from the cell's: the excess is the quadrature error. The
// swept means' own quadrature error: measured at most 7.1e-3 (a slab of
// width 0.05 with its 2 nodes across the step), bound 1e-2.
TEST(Mthinc, SweptMeansAreTheStepsMeansAndKeepAnEulerStepBounded) {
  const double beta = 3.5;
  double worst = 0;
  for (const auto& n : normals())
    for (double q : {1e-9, 1e-5, 0.2, 0.5, 0.95, 1 - 1e-9})
      for (int ax = 0; ax < 3; ++ax)
        for (bool high : {true, false})
          for (double nu : {0.05, 0.4, 1.0}) {
            const double g[3] = {n[0], n[1], n[2]};
            MthincExps x;
            const MthincPlane p = mthinc_fit(q, g, beta, x);
            const double f = mthinc_face_value(p, x, q, beta, ax, high, nu);
            // the same value from the general box mean, which takes its own exps
            double blo[3] = {-0.5, -0.5, -0.5}, bhi[3] = {0.5, 0.5, 0.5};
            (high ? blo[ax] : bhi[ax]) = high ? 0.5 - nu : -0.5 + nu;
            EXPECT_NEAR(f, mthinc_box_mean(p, x, q, beta, blo, bhi), 1e-13)
                << "ax " << ax << " q " << q << " nu " << nu;
            double lo[3] = {-0.5, -0.5, -0.5}, hi[3] = {0.5, 0.5, 0.5};
            if (high)
              lo[ax] = 0.5 - nu;
            else
              hi[ax] = -0.5 + nu;
            const double e = std::fabs(f - brute_mean(p, x, beta, lo, hi, 60));
            worst = std::max(worst, e);
            EXPECT_LT(e, 1e-2) << "ax " << ax << " q " << q << " nu " << nu;
            EXPECT_GE(f, 0.0);
            EXPECT_LE(f, 1.0);
            const double tol = ax == p.dom ? 1e-13 : 5e-3;
            EXPECT_GE(q - nu * f, -tol) << "out of the cell: ax " << ax << " q " << q << " nu " << nu;
            EXPECT_LE(q + nu * (1 - f), 1 + tol) << "into the cell: ax " << ax << " q " << q << " nu " << nu;
          }
  std::printf("  largest quadrature error of a swept mean: %.1e\n", worst);
}

// The tails' closed forms (1 / u for H, u for 1 - H) against the full form on
// the same nodes, for every face of cells of every orientation just inside
// the tails. The tail form is off by 1/u relative, at most the largest H over
// the slab, up to about 9 q at beta = 3.5 (kernels/mthinc.hpp): so by about
// 81 q^2, 8e-13 at q = mthinc_tail (measured 5e-13).
TEST(Mthinc, TailFormsAreTheFullFormsTo1e12) {
  const double beta = 3.5;
  double worst = 0;
  for (const auto& n : normals())
    for (double t : {0.99 * mthinc_tail, 1e-9})
      for (int side : {-1, 1}) {
        const double q = side < 0 ? t : 1 - t;
        const double g[3] = {n[0], n[1], n[2]};
        MthincExps x;
        const MthincPlane p = mthinc_fit(q, g, beta, x);
        ASSERT_EQ(mthinc_side(q), side);
        const int D = p.dom;
        const double nD = std::fabs(p.n[D]);
        double k[4];
        mthinc_nodes(x.E, x.e1, x.e2, k);
        for (double nu : {0.05, 0.4, 1.0})
          for (double a : {-0.5, 0.5 - nu}) {  // a slab along D at each end (the frame where n_D > 0)
            const double b = a + nu, ea = std::exp(-2 * beta * nD * a), eb = std::exp(-2 * beta * nD * b);
            const double tail = mthinc_mean_along(k, beta, nD, a, b, ea, eb, side);
            const double full = mthinc_mean_along(k, beta, nD, a, b, ea, eb, 0);
            worst = std::max(worst, std::fabs(tail - full));
            EXPECT_LT(std::fabs(tail - full), 1e-12) << "q " << q << " nu " << nu << " a " << a;
          }
        // the tail fit gives q back in the tail form, to rounding
        const double lo[3] = {-0.5, -0.5, -0.5}, hi[3] = {0.5, 0.5, 0.5};
        EXPECT_NEAR(mthinc_box_mean(p, x, q, beta, lo, hi), q, 1e-15 + 1e-13 * t) << "q " << q;
      }
  std::printf("  tail forms against the full ones: at most %.1e\n", worst);
}
