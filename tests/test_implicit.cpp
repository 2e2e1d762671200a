// The implicit viscous step (kernels/implicit_viscous.hpp): the stability map
// of its split, the Helmholtz solves, and the verification of the explicit
// scheme repeated with it: order in time and space on the start-up and
// manufactured problems.
#include <gtest/gtest.h>

#include <cmath>

#include "../kernels/implicit_viscous.hpp"
#include "../kernels/rk3_update.hpp"
#include "diagnostics.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

// Amplification of one RK3 step for a Fourier mode of the split viscous term:
// nu0 L implicit (Crank-Nicolson per stage), (nu - nu0) L explicit, with
// z = nu0 k^2 dt and r = nu / nu0. rk_weights: the remainder weighted like
// the advection (gamma, zeta); otherwise alpha per stage (what the code does).
double split_amplification(double z, double r, bool rk_weights) {
  const double e = (1 - r) * z, m = -z;  // remainder and implicit eigenvalues times dt
  double before = 1, now = 1;            // u at the previous and the current stage
  for (int s = 0; s < Rk3::stages; ++s) {
    const double a = Rk3::alpha[s];
    const double expl = rk_weights ? Rk3::gamma[s] * e * now + Rk3::zeta[s] * e * before : a * e * now;
    const double next = (now + expl + a * m / 2 * now) / (1 - a * m / 2);
    before = now;
    now = next;
  }
  return std::abs(now);
}

double worst_amplification(double r, bool rk_weights) {
  double worst = 0;
  for (int n = 0; n <= 900; ++n)
    worst = std::max(worst, split_amplification(std::pow(10.0, -3 + n / 100.0), r, rk_weights));
  return worst;
}

// reproducible pseudo-random values from a global index (same on any rank grid)
KOKKOS_INLINE_FUNCTION double hash01(long n) {
  unsigned long x = (unsigned long)n * 0x9E3779B97F4A7C15ul + 0x632BE59BD9B4E019ul;
  x ^= x >> 31;
  x *= 0xBF58476D1CE4E5B9ul;
  x ^= x >> 27;
  return double(x % 1000003ul) / 1000003.0 - 0.5;
}

void random_pencil(const Grid& g, const Array1& r, int salt) {
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl, nx = g.nx, x0 = g.x0, z0 = g.z0;
  par_for(
      "test_random_pencil", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const long gid = (x0 + i - ng) + long(nx) * ((j - ng) + long(ny) * (z0 + k - ng));
        r(PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl)) = hash01(gid * 3 + salt);
      });
}

// max |x - beta L x - r| of one component (its ghosts set by the walls)
double helmholtz_residual(const Grid& g, const Field3& x, const Array1& r, Real beta, bool face) {
  const AdvectionDiffusion op{1 / g.dx, 1 / g.dy, 1 / g.dz};
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl, vtop = Grid::ng + g.ny - 1;
  double m = 0;
  par_reduce(
      "test_helmholtz_residual", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& e) {
        if (face && j == vtop) return;
        const double d =
            x(i, j, k) - beta * op.lap(x, i, j, k) - r(PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl));
        e = Kokkos::fmax(e, Kokkos::fabs(d));
      },
      Kokkos::Max<double>(m));
  return global_max(m);
}

// u of the start-up problem (walls at +-1 moving at +-1, nu = 1) at time t
double startup_exact(double y, double t) {
  double s = y;
  for (int n = 1; n < 20000; ++n) {
    const double d = std::exp(-n * n * M_PI * M_PI * t);
    if (d < 1e-20) break;
    s += 2 * (n % 2 ? -1.0 : 1.0) / (n * M_PI) * std::sin(n * M_PI * y) * d;
  }
  return s;
}

// the start-up profile at time t0 in u (the smooth part of the start-up: the
// impulsive start itself is not smooth in time)
void set_startup(FlowSolver& s, double t0) {
  const Grid g = s.grid();
  auto h = Kokkos::create_mirror_view(s.state().u);
  Kokkos::deep_copy(h, s.state().u);
  for (int j = Grid::ng; j < Grid::ng + g.ny; ++j) {
    const double val = startup_exact(g.yc(j), t0);
    for (int k = 0; k < g.sz(); ++k)
      for (int i = 0; i < g.sx(); ++i) h(i, j, k) = val;
  }
  Kokkos::deep_copy(s.state().u, h);
  s.time = t0;
  s.fill_velocity_ghosts();
}

double startup_error(FlowSolver& s) {
  FlowProfiles p = Diagnostics(s).profiles();
  double e = 0;
  for (size_t j = 0; j < p.y_centre.size(); ++j)
    e = std::max(e, std::abs(p.u_mean[j] - startup_exact(p.y_centre[j], s.time)));
  return e;
}

Config implicit_case(int nx, int ny, int nz, std::vector<std::string> extra = {}) {
  extra.push_back("time.viscous=\"implicit\"");
  return couette_case(nx, ny, nz, extra);
}

}  // namespace

TEST(ImplicitViscous, SplitIsStableForEveryViscosityUpToTheImplicitOne) {
  // the scheme's choice: remainder weighted alpha per stage, nu0 = max nu
  for (double r : {0.0, 0.01, 0.1, 0.3, 0.5, 0.9, 1.0})
    EXPECT_LE(worst_amplification(r, false), 1 + 1e-12) << "nu / nu0 = " << r;
  // a viscosity above nu0 is not: hence nu0 = max(mu_f, mu_s) / rho
  EXPECT_GT(worst_amplification(1.1, false), 1.5);
  // the remainder weighted like the advection is unstable between about
  // 0.06 and 0.63, which K = 0.1 or 10 would reach: why the code does not
  for (double r : {0.1, 0.3, 0.5}) EXPECT_GT(worst_amplification(r, true), 2.0) << "nu / nu0 = " << r;
  EXPECT_LE(worst_amplification(0.9, true), 1 + 1e-12);
  if (world_rank() == 0)
    std::printf(
        "  max |A| over dt: alpha-weighted remainder %.4f (r=0.1) %.4f (r=0.5); "
        "RK-weighted %.3f (r=0.1) %.3f (r=0.5)\n",
        worst_amplification(0.1, false), worst_amplification(0.5, false), worst_amplification(0.1, true),
        worst_amplification(0.5, true));
}

TEST(ImplicitViscous, HelmholtzSolvesReachRoundOff) {
  // walls at rest: the ghosts hold the homogeneous Dirichlet conditions
  Config c = implicit_case(16, 12, 8, {"walls.velocity=0.0"});
  FlowSolver s(c, MPI_COMM_WORLD);
  const Grid g = s.grid();
  const size_t n = s.poisson().rhs().size();
  Array1 r[3], x[3];
  for (int m = 0; m < 3; ++m) {
    r[m] = Array1("r", n);
    x[m] = Array1("x", n);
    random_pencil(g, r[m], m);
    Kokkos::deep_copy(x[m], r[m]);
  }
  for (double beta : {1e-3, 0.5}) {
    for (int m = 0; m < 3; ++m) {
      Kokkos::deep_copy(x[m], r[m]);
      s.poisson().solve(x[m], {1, -beta, m == 1 ? WallRows::dirichlet_face : WallRows::dirichlet_centre});
    }
    implicit_to_velocity(g, s.state(), x[0], x[1], x[2]);
    s.fill_velocity_ghosts(0.0);
    const double eu = helmholtz_residual(g, s.state().u, r[0], beta, false);
    const double ev = helmholtz_residual(g, s.state().v, r[1], beta, true);
    const double ew = helmholtz_residual(g, s.state().w, r[2], beta, false);
    if (world_rank() == 0) std::printf("  beta %.0e: residuals u %.1e v %.1e w %.1e\n", beta, eu, ev, ew);
    EXPECT_LT(std::max({eu, ev, ew}), 1e-12);
  }
}

TEST(ImplicitViscous, StartupSecondOrderInTime) {
  // fixed grid, dt halved from about 25x to 6x the explicit viscous limit;
  // the difference to a run with dt / 16 measures the time error alone
  const double t0 = 0.02, t1 = 0.1;
  auto run = [&](int steps) {
    auto s = std::make_unique<FlowSolver>(implicit_case(4, 32, 4), MPI_COMM_WORLD);
    s->initialize();
    set_startup(*s, t0);
    for (int n = 0; n < steps; ++n) s->advance((t1 - t0) / steps);
    return s;
  };
  auto ref = run(64);
  std::vector<double> dts, errs;
  for (int steps : {4, 8, 16}) {
    auto s = run(steps);
    double e = global_max(max_diff(s->state().u, ref->state().u, s->grid().interior()));
    dts.push_back((t1 - t0) / steps);
    errs.push_back(e);
    const Grid& g = s->grid();
    const double explicit_dt = 2.51 / (4 * (1 / (g.dx * g.dx) + 1 / (g.dy * g.dy) + 1 / (g.dz * g.dz)));
    if (world_rank() == 0)
      std::printf("  dt = %.4f (%.0fx the explicit limit)  difference to dt/16 %.3e, error vs exact %.3e\n",
                  dts.back(), dts.back() / explicit_dt, e, startup_error(*s));
  }
  const double q = order(dts, errs);
  if (world_rank() == 0) std::printf("  observed order in time: %.3f\n", q);
  EXPECT_GT(q, 1.9);
  EXPECT_LT(q, 2.3);
}

TEST(ImplicitViscous, StartupSecondOrderInY) {
  // from rest, the impulsive start included, dt tied to dy so the time error
  // shrinks with the space error
  const double t_end = 0.1;
  std::vector<double> hs, errs;
  for (int ny : {16, 32, 64}) {
    FlowSolver s(implicit_case(4, ny, 4), MPI_COMM_WORLD);
    s.initialize();
    run_to(s, t_end, 0.05 * s.grid().dy);
    hs.push_back(s.grid().dy);
    errs.push_back(startup_error(s));
    if (world_rank() == 0) std::printf("  ny = %3d  max error %.3e\n", ny, errs.back());
  }
  const double q = order(hs, errs);
  if (world_rank() == 0) std::printf("  observed order in y: %.3f\n", q);
  EXPECT_GT(q, 1.9);
  EXPECT_LT(q, 2.3);
}
