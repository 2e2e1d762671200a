// The oscillating fluid/solid sandwich of Sugiyama et al. (JCP 2011): a
// neo-Hookean layer |y| < a bonded to Newtonian layers a < |y| < h, between
// walls oscillating in their own plane at +-V cos(omega t). By antisymmetry
// y = 0 is a fixed plane. The problem is 1-D and exactly linear: in simple
// shear dB_12/dt = du/dy and B_22 = 1, so the solid's shear stress is
// mu_s du/dy + G B_12 (Kelvin-Voigt). The time-periodic solution is
// u = Re[U(y) e^{i omega t}] with, for mu_e = mu_s + G / (i omega),
// k_f^2 = i omega rho / mu_f and k_s^2 = i omega rho / mu_e:
//   solid  U = C sinh(k_s y)
//   fluid  U = D sinh(k_f (y - a)) + E cosh(k_f (y - a))
// continuity of U and of the shear stress at y = a, U(h) = V:
//   E = C sinh(k_s a),  mu_f k_f D = mu_e k_s C cosh(k_s a),
//   C [mu_e k_s cosh(k_s a) sinh(k_f L) / (mu_f k_f) + sinh(k_s a) cosh(k_f L)] = V,  L = h - a.
#include <gtest/gtest.h>

#include <complex>

#include "diagnostics.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;
using cd = std::complex<double>;

namespace {

struct Sandwich {
  double rho = 1, mu_f = 1, mu_s = 1, G = 4, omega = 2 * M_PI, V = 1, a = 0.5, h = 1;
  double u(double y, double t) const {
    const cd I(0, 1);
    const cd mu_e = mu_s + G / (I * omega);
    const cd kf = std::sqrt(I * omega * rho / mu_f), ks = std::sqrt(I * omega * rho / mu_e);
    const double L = h - a;
    const cd C = V / (mu_e * ks * std::cosh(ks * a) * std::sinh(kf * L) / (mu_f * kf) +
                      std::sinh(ks * a) * std::cosh(kf * L));
    const double s = y < 0 ? -1 : 1, ya = std::abs(y);
    cd U;
    if (ya <= a) {
      U = C * std::sinh(ks * ya);
    } else {
      const cd E = C * std::sinh(ks * a), D = mu_e * ks * C * std::cosh(ks * a) / (mu_f * kf);
      U = D * std::sinh(kf * (ya - a)) + E * std::cosh(kf * (ya - a));
    }
    return s * std::real(U * std::exp(I * omega * t));
  }
};

// max error of the plane-averaged u over y, at four phases of the fifth period
double sandwich_error(int ny, const std::string& scheme) {
  const Sandwich ex;
  Config c = couette_case(
      4, ny, 4,
      {"grid.lx=1.0", "grid.lz=1.0", "walls.velocity=1.0", "walls.omega=" + std::to_string(ex.omega),
       "particles.shape=layer", "particles.layer_thickness=1.0", "particles.shear_modulus=4.0",
       "particles.viscosity_ratio=1.0", "time.viscous=\"" + scheme + "\""});
  FlowSolver s(c, MPI_COMM_WORLD);
  s.initialize();
  double e = 0;
  for (double t : {4.0, 4.25, 4.5, 4.75}) {
    run_to(s, t);
    FlowProfiles p = Diagnostics(s).profiles();
    for (size_t j = 0; j < p.y_centre.size(); ++j)
      e = std::max(e, std::abs(p.u_mean[j] - ex.u(p.y_centre[j], t)));
  }
  return e;
}

}  // namespace

TEST(Sandwich, ExactSolutionIsConsistent) {
  const Sandwich ex;
  const double t = 0.3, d = 1e-6;
  EXPECT_NEAR(ex.u(1.0, t), std::cos(ex.omega * t), 1e-12);         // the wall
  EXPECT_NEAR(ex.u(0.0, t), 0.0, 1e-14);                            // the symmetry plane
  EXPECT_NEAR(ex.u(ex.a - 1e-12, t), ex.u(ex.a + 1e-12, t), 1e-9);  // continuity at the interface
  // the fluid obeys u_t = nu u_yy at y = 0.75
  const double y = 0.75;
  const double ut = (ex.u(y, t + d) - ex.u(y, t - d)) / (2 * d);
  const double uyy = (ex.u(y + 1e-3, t) - 2 * ex.u(y, t) + ex.u(y - 1e-3, t)) / 1e-6;
  EXPECT_NEAR(ut, ex.mu_f / ex.rho * uyy, 1e-4 * std::abs(ut) + 1e-6);
}

class SandwichScheme : public ::testing::TestWithParam<const char*> {};

TEST_P(SandwichScheme, MatchesTheExactPeriodicSolutionAndConverges) {
  std::vector<double> hs, errs;
  for (int ny : {32, 64}) {
    errs.push_back(sandwich_error(ny, GetParam()));
    hs.push_back(2.0 / ny);
    if (world_rank() == 0)
      std::printf("  %s, ny = %d  max |u - u_exact| / V = %.3e\n", GetParam(), ny, errs.back());
  }
  const double q = std::log(errs[0] / errs[1]) / std::log(2.0);
  if (world_rank() == 0) std::printf("  observed order %.2f\n", q);
  // the interface cell's mixture viscosity and elastic stress are first-order
  // accurate in space (measured: explicit 3.7e-3 -> 1.5e-3, order 1.3)
  EXPECT_LT(errs.back(), 0.02);
  EXPECT_GT(q, 0.9);
}

INSTANTIATE_TEST_SUITE_P(Viscous, SandwichScheme, ::testing::Values("explicit", "implicit"));
