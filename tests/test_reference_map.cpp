// The reference map's point-wise parts (kernels/reference_map.hpp), on the
// host: the band's affine fit, B from grad xi, a cell's share of the sphere.
#include <gtest/gtest.h>

#include <cmath>

#include "../kernels/reference_map.hpp"

using namespace softflow;

TEST(ReferenceMap, AffineFitRecoversAnAffineMapFromOneSide) {
  // xi = a + G o sampled on the half block o_x < 0 of a 7^3 block (a band
  // cell beside the solid): the fit's value at the centre is a, to round-off
  const Real a[3] = {0.3, -1.2, 2.5};
  const Real G[3][3] = {{1.4, 0.3, -0.2}, {0.1, 0.7, 0.05}, {-0.3, 0.2, 1.1}};
  AffineFit fit;
  const Real h = 0.25;
  for (int c = -3; c <= 3; ++c)
    for (int b = -3; b <= 3; ++b)
      for (int e = -3; e <= -1; ++e) {
        const Real o[3] = {e * h, b * h, c * h};
        Real v[3];
        for (int m = 0; m < 3; ++m) v[m] = a[m] + G[m][0] * o[0] + G[m][1] * o[1] + G[m][2] * o[2];
        fit.add(o, v, 1 / Real(e * e + b * b + c * c));
      }
  Real out[3];
  ASSERT_TRUE(fit.solve(out));
  for (int m = 0; m < 3; ++m) EXPECT_NEAR(out[m], a[m], 1e-12);
}

TEST(ReferenceMap, AffineFitRefusesCoplanarPoints) {
  AffineFit fit;
  for (int b = -2; b <= 2; ++b)
    for (int c = -2; c <= 2; ++c) {
      const Real o[3] = {-0.25, b * 0.25, c * 0.25}, v[3] = {1, 2, 3};
      fit.add(o, v, 1);
    }
  Real out[3];
  EXPECT_FALSE(fit.solve(out));
}

TEST(ReferenceMap, BIsTheInverseMapsGramMatrix) {
  // simple shear x = X + g Y: xi = (x - g y, y, z), J = [[1, -g, 0], [0, 1, 0],
  // [0, 0, 1]]; B = F F^T = [[1 + g^2, g, 0], [g, 1, 0], [0, 0, 1]]
  const Real g = 0.7;
  const Real J[3][3] = {{1, -g, 0}, {0, 1, 0}, {0, 0, 1}};
  Real B[6];
  b_from_map_gradient(J, B);
  const Real want[6] = {1 + g * g, g, 0, 1, 0, 1};
  for (int m = 0; m < 6; ++m) EXPECT_NEAR(B[m], want[m], 1e-14) << m;
}

TEST(ReferenceMap, ABrokenMapGivesTheIdentity) {
  const Real J[3][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
  Real B[6];
  b_from_map_gradient(J, B);
  EXPECT_EQ(B[0], 1);
  EXPECT_EQ(B[1], 0);
  EXPECT_EQ(B[3], 1);
}

// the band's soft edge: a cell keeps all of its own value while it maps into
// the sphere, none beyond width of it, and the share falls linearly between
// (so a cell leaving the sphere hands its value to the fit continuously)
TEST(ReferenceMap, SoftEdgeWeightFallsFromOneToZeroAcrossItsWidth) {
  const Real r = 2, width = 0.5;
  const Real dir[3] = {0.48, -0.6, 0.64};  // a unit vector
  const auto at = [&](Real rho) {
    const Real q[3] = {rho * dir[0], rho * dir[1], rho * dir[2]};
    return soft_edge_weight(q, r, width);
  };
  EXPECT_EQ(at(0), 1);
  EXPECT_EQ(at(1.99), 1);
  EXPECT_NEAR(at(2.0), 1, 1e-14);
  EXPECT_NEAR(at(2.125), 0.75, 1e-14);
  EXPECT_NEAR(at(2.25), 0.5, 1e-14);
  EXPECT_NEAR(at(2.5), 0, 1e-14);
  EXPECT_EQ(at(2.51), 0);
  EXPECT_EQ(at(30), 0);  // the far value
}

TEST(ReferenceMap, CellSharesOfTheSphereSumToItsVolume) {
  // the undeformed map xi = x on a grid of cells of side h: the shares of
  // the unit sphere sum to 4 pi / 3 within the ramp's second-order error,
  // and an affine map of det 1 (a stretch) keeps that volume
  for (const Real s : {1.0, 2.0}) {
    const Real h = 0.25, hh[3] = {h, h, h};
    const Real J[3][3] = {{1 / s, 0, 0}, {0, s, 0}, {0, 0, 1}};  // xi = (x / s, s y, z)
    Real v = 0;
    const int n = int(std::ceil(1.6 * s / h));
    for (int i = -n; i < n; ++i)
      for (int j = -n; j < n; ++j)
        for (int k = -n; k < n; ++k) {
          const Real x[3] = {(i + 0.5) * h, (j + 0.5) * h, (k + 0.5) * h};
          const Real d[3] = {x[0] / s, s * x[1], x[2]};
          v += reference_ball_share(d, J, 1, hh, 4) * h * h * h;
        }
    EXPECT_NEAR(v, 4 * M_PI / 3, 2e-3 * 4 * M_PI / 3) << "stretch " << s;
  }
}
