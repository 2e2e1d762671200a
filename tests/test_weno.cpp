// WENO5: fifth order point-wise, in the 3-D transport operator, and in time
// integration with dt ~ dx^(5/3).
#include <gtest/gtest.h>

#include "../kernels/solid_transport.hpp"
#include "../kernels/weno5.hpp"
#include "solid_util.hpp"

using namespace softflow;
using namespace softflow::test;

TEST(Weno5, ReconstructsFaceValuesAtFifthOrder) {
  // cell averages of sin(2 pi x) on [0, 1] -> value at the right face of each
  // cell
  std::vector<double> hs, errs;
  for (int n : {16, 32, 64, 128}) {
    const double dx = 1.0 / n;
    auto avg = [&](int c) {
      const double a = c * dx, b = a + dx;
      return (std::cos(2 * M_PI * a) - std::cos(2 * M_PI * b)) / (2 * M_PI * dx);
    };
    double e = 0, e_left = 0;
    for (int c = 0; c < n; ++c) {
      const double face = std::sin(2 * M_PI * (c + 1) * dx);
      e = std::max(e, std::abs(weno5(avg(c - 2), avg(c - 1), avg(c), avg(c + 1), avg(c + 2)) - face));
      // from the right: flow in -x
      e_left = std::max(e_left, std::abs(weno5_face(-1, avg(c - 2), avg(c - 1), avg(c), avg(c + 1),
                                                    avg(c + 2), avg(c + 3)) -
                                         face));
    }
    hs.push_back(dx);
    errs.push_back(std::max(e, e_left));
  }
  const double q = order(hs, errs);
  std::printf("  point-wise WENO5 order: %.3f (errors %.2e .. %.2e)\n", q, errs.front(), errs.back());
  EXPECT_GT(q, 4.7);
}

TEST(Weno5, NoNewExtremaAcrossAJump) {
  // a step: the reconstruction stays within the data's range (to a few percent)
  double lo = 1, hi = 0;
  for (int c = 0; c < 10; ++c) {
    auto q = [&](int k) { return k < 5 ? 0.0 : 1.0; };
    const double f = weno5(q(c - 2), q(c - 1), q(c), q(c + 1), q(c + 2));
    lo = std::min(lo, f), hi = std::max(hi, f);
  }
  EXPECT_GT(lo, -0.02);
  EXPECT_LT(hi, 1.02);
}

namespace {
struct Uniform {
  double U, V, W;
  KOKKOS_INLINE_FUNCTION Vec3 operator()(double, double, double, double) const { return {U, V, W}; }
};
// smooth fields, periodic in the box
struct Smooth {
  double a, b, c;
  KOKKOS_INLINE_FUNCTION double value(int m, double x, double y, double z) const {
    return (m == 0                         ? 0.5
            : (m == 1 || m == 4 || m == 6) ? 1.0
                                           : 0.0) +
           0.2 / (1 + m) * Kokkos::sin(a * x + 0.3 * m) * Kokkos::sin(b * y + 0.7) *
               Kokkos::sin(c * z + 1.1 + m);
  }
  KOKKOS_INLINE_FUNCTION double grad_dot(int m, double x, double y, double z, double U, double V,
                                         double W) const {
    const double A = 0.2 / (1 + m);
    const double sx = Kokkos::sin(a * x + 0.3 * m), cx = Kokkos::cos(a * x + 0.3 * m);
    const double sy = Kokkos::sin(b * y + 0.7), cy = Kokkos::cos(b * y + 0.7);
    const double sz = Kokkos::sin(c * z + 1.1 + m), cz = Kokkos::cos(c * z + 1.1 + m);
    return A * (U * a * cx * sy * sz + V * b * sx * cy * sz + W * c * sx * sy * cz);
  }
};
}  // namespace

namespace {
// Device loops of the tests below live outside the TEST bodies: nvcc forbids
// extended (KOKKOS_LAMBDA) lambdas in gtest's private TestBody.
void fill_smooth(const Grid& g, const SolidViews& qv, const Smooth& f) {
  par_for(
      "test_fill_smooth", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        for (int m = 0; m < n_solid_fields; ++m) qv.field(m)(i, j, k) = f.value(m, g.xc(i), g.yc(j), g.zc(k));
      });
}
double transport_error(const Grid& g, const Field3& r, const Smooth& f, int m, const Uniform& vel) {
  return max_error(
      g, r, KOKKOS_LAMBDA(int i, int j, int k) {
        return -f.grad_dot(m, g.xc(i), g.yc(j), g.zc(k), vel.U, vel.V, vel.W);
      });
}
// f_0 carried by the uniform velocity for a time t
void fill_advected(const Grid& g, const Field3& phi, const Smooth& f, const Uniform& vel, double t) {
  par_for(
      "test_fill_phi", g.all(), KOKKOS_LAMBDA(int i, int j, int k) {
        phi(i, j, k) = f.value(0, g.xc(i) - vel.U * t, g.yc(j), g.zc(k) - vel.W * t);
      });
}
double advected_error(const Grid& g, const Field3& phi, const Smooth& f, const Uniform& vel, double t) {
  return max_error(
      g, phi, KOKKOS_LAMBDA(int i, int j, int k) {
        return f.value(0, g.xc(i) - vel.U * t, g.yc(j), g.zc(k) - vel.W * t);
      });
}
}  // namespace

TEST(Weno5, TransportOperatorIsFifthOrderInAllDirections) {
  const Uniform vel{1.0, 0.7, -0.4};
  std::vector<double> hs, errs;
  for (int n : {16, 32, 64}) {
    Config c = couette_case(n, n, n, solid_keys({"grid.lx=1.0", "grid.ly=1.0", "grid.lz=1.0"}));
    FlowSolver s(c, MPI_COMM_WORLD);
    const Grid g = s.grid();
    const Smooth f{2 * M_PI, 2 * M_PI, 2 * M_PI};
    set_velocity(s, vel, 0);
    SolidFields q(g, "q"), r(g, "r");
    const SolidViews qv(q);
    fill_smooth(g, qv, f);
    solid_transport_rhs(g, s.state(), q, r, FaceFluxes(g), g.interior(), g.interior());
    double e = 0;
    for (int m = 0; m < n_solid_fields; ++m) {
      e = std::max(e, transport_error(g, r.q[m], f, m, vel));
    }
    hs.push_back(g.dx);
    errs.push_back(e);
    if (world_rank() == 0) std::printf("  n = %d  max error %.3e\n", n, e);
  }
  const double q = order(hs, errs);
  if (world_rank() == 0) std::printf("  transport operator order: %.3f\n", q);
  EXPECT_GT(q, 4.6);
}

TEST(Weno5, AdvectionInTimeIsFifthOrderWithDtLikeDxToFiveThirds) {
  // periodic 1-D advection in x (v = 0: the walls see nothing) over one period;
  // the 3-D operator's order is checked above
  const Uniform vel{1.0, 0.0, 0.0};
  std::vector<double> hs, errs;
  for (int n : {24, 48, 96}) {
    Config c = couette_case(
        n, 4, 4, solid_keys({"grid.lx=1.0", "grid.ly=1.0", "grid.lz=1.0", "particles.phi_scheme=weno5"}));
    FlowSolver s(c, MPI_COMM_WORLD);
    const Grid g = s.grid();
    const Smooth f{2 * M_PI, 0.0, 0.0};
    const SolidViews q(s.solid()->fields());
    fill_advected(g, q.phi, f, vel, 0);
    s.solid()->fill_ghosts();
    const double T = 1.0;  // one period
    const int steps = int(std::ceil(T / (0.5 * std::pow(g.dx, 5.0 / 3.0))));
    for (int k = 0; k < steps; ++k) transport_step(s, vel, T / steps);
    const double e = advected_error(g, q.phi, f, vel, T);
    hs.push_back(g.dx);
    errs.push_back(e);
    if (world_rank() == 0) std::printf("  n = %d  steps %d  max error %.3e\n", n, steps, e);
  }
  const double q = order(hs, errs);
  if (world_rank() == 0) std::printf("  advection order (space and time): %.3f\n", q);
  EXPECT_GT(q, 4.5);
}
