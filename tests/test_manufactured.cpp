// The manufactured solution: its forcing is consistent with its fields, and
// the solver converges to it at second order in space and in time.
#include <gtest/gtest.h>

#include <random>

#include "../kernels/manufactured.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

Manufactured sample_mms() {
  Manufactured m;
  m.enabled = true;
  m.amp = 0.7, m.omega = 1.3, m.a = 2 * M_PI / 2.1, m.c = 2 * M_PI / 1.7, m.h = 0.8, m.vw = 0.9, m.nu = 0.37;
  return m;
}

// max error of u, v, w against the exact solution at time s.time, over the unknowns
double error_vs_exact(FlowSolver& s) {
  const Grid g = s.grid();
  const Manufactured m = s.manufactured();
  auto u = s.state().u, v = s.state().v, w = s.state().w;
  const double t = s.time;
  const int vtop = Grid::ng + g.ny - 1;
  double e = 0;
  par_reduce(
      "test_mms_error", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& x) {
        double d = Kokkos::fabs(u(i, j, k) - m.eval(g.xf(i), g.yc(j), g.zc(k), t).u);
        d = Kokkos::fmax(d, Kokkos::fabs(w(i, j, k) - m.eval(g.xc(i), g.yc(j), g.zf(k), t).w));
        if (j < vtop) d = Kokkos::fmax(d, Kokkos::fabs(v(i, j, k) - m.eval(g.xc(i), g.yf(j), g.zc(k), t).v));
        x = Kokkos::fmax(x, d);
      },
      Kokkos::Max<double>(e));
  return global_max(e);
}

Config mms_case(int nx, int ny, int nz, const std::string& scheme = "explicit") {
  return couette_case(nx, ny, nz,
                      {"initial.type=manufactured", "initial.amplitude=1.0", "initial.omega=2.0",
                       "fluid.mu=0.1", "grid.lx=2.0", "grid.lz=2.0", "time.viscous=\"" + scheme + "\""});
}

}  // namespace

TEST(Manufactured, FieldsAreDivergenceFreeAndForcingMatchesFiniteDifferences) {
  const Manufactured m = sample_mms();
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> U(-1, 1);
  const double e = 1e-4;
  for (int n = 0; n < 50; ++n) {
    const double x = 3 * U(gen), y = m.h * U(gen), z = 3 * U(gen), t = 2 + U(gen);
    auto q = m.eval(x, y, z, t);
    EXPECT_NEAR(q.ux + q.vy + q.wz, 0, 1e-12);
    auto P = [&](double dx, double dy, double dz, double dt) {
      return m.eval(x + dx, y + dy, z + dz, t + dt);
    };
    // first derivatives by central differences (error ~ e^2)
    auto fd = [&](auto get, int dir) {
      double d[4] = {0, 0, 0, 0};
      d[dir] = e;
      auto p = P(d[0], d[1], d[2], d[3]);
      d[dir] = -e;
      auto mm = P(d[0], d[1], d[2], d[3]);
      return (get(p) - get(mm)) / (2 * e);
    };
    auto lap = [&](auto get) {
      double s = 0;
      for (int dir = 0; dir < 3; ++dir) {
        double d[3] = {0, 0, 0};
        d[dir] = e;
        auto p = P(d[0], d[1], d[2], 0);
        d[dir] = -e;
        auto mm = P(d[0], d[1], d[2], 0);
        s += (get(p) - 2 * get(q) + get(mm)) / (e * e);
      }
      return s;
    };
    auto gu = [](const Manufactured::Point& p) { return p.u; };
    auto gv = [](const Manufactured::Point& p) { return p.v; };
    auto gw = [](const Manufactured::Point& p) { return p.w; };
    const double tol = 1e-6;
    EXPECT_NEAR(q.ux, fd(gu, 0), tol);
    EXPECT_NEAR(q.uy, fd(gu, 1), tol);
    EXPECT_NEAR(q.uz, fd(gu, 2), tol);
    EXPECT_NEAR(q.vx, fd(gv, 0), tol);
    EXPECT_NEAR(q.vy, fd(gv, 1), tol);
    EXPECT_NEAR(q.vz, fd(gv, 2), tol);
    EXPECT_NEAR(q.wx, fd(gw, 0), tol);
    EXPECT_NEAR(q.wy, fd(gw, 1), tol);
    EXPECT_NEAR(q.wz, fd(gw, 2), tol);
    EXPECT_NEAR(q.ut, fd(gu, 3), tol);
    EXPECT_NEAR(q.vt, fd(gv, 3), tol);
    EXPECT_NEAR(q.wt, fd(gw, 3), tol);
    EXPECT_NEAR(q.lu, lap(gu), 1e-4);
    EXPECT_NEAR(q.lv, lap(gv), 1e-4);
    EXPECT_NEAR(q.lw, lap(gw), 1e-4);
    // pressure: p = A g(y) cos(ax) sin(cz); check its gradient through the forcing's definition
    const double A = m.amp * std::cos(m.omega * t), eta = y / m.h;
    auto p = [&](double X, double Y, double Z) {
      const double et = Y / m.h;
      return A * (et - et * et * et / 3) * std::cos(m.a * X) * std::sin(m.c * Z);
    };
    (void)eta;
    EXPECT_NEAR(q.px, (p(x + e, y, z) - p(x - e, y, z)) / (2 * e), tol);
    EXPECT_NEAR(q.py, (p(x, y + e, z) - p(x, y - e, z)) / (2 * e), tol);
    EXPECT_NEAR(q.pz, (p(x, y, z + e) - p(x, y, z - e)) / (2 * e), tol);
    EXPECT_NEAR(m.force(0, x, y, z, t), q.ut + q.u * q.ux + q.v * q.uy + q.w * q.uz - m.nu * q.lu + q.px,
                1e-12);
  }
  // the walls: no slip and no penetration
  for (double y : {-m.h, m.h}) {
    auto q = m.eval(0.3, y, 0.4, 0.5);
    EXPECT_NEAR(q.u, y > 0 ? m.vw : -m.vw, 1e-14);
    EXPECT_NEAR(q.v, 0, 1e-14);
    EXPECT_NEAR(q.w, 0, 1e-14);
  }
}

namespace {

// max error against the exact solution at t = 0.3 on 12^3, 24^3, 48^3: the
// observed order of the finest pair (the coarser ones approach 2 from below).
// Explicit: dt tied to the viscous limit (~dx^2), time errors negligible;
// implicit: dt = 0.2 dy, time errors second order too.
double space_order(const std::string& scheme) {
  const double t_end = 0.3;
  std::vector<double> hs, errs;
  for (int n : {12, 24, 48}) {
    Config c = mms_case(n, n, n, scheme);
    FlowSolver s(c, MPI_COMM_WORLD);
    s.initialize();
    run_to(s, t_end, 0.2 * s.grid().dy);
    hs.push_back(s.grid().dy);
    errs.push_back(error_vs_exact(s));
    if (world_rank() == 0)
      std::printf("  %s, n = %3d  max error %.3e (%ld steps)\n", scheme.c_str(), n, errs.back(), s.step);
  }
  const double q = std::log(errs[1] / errs[2]) / std::log(hs[1] / hs[2]);
  if (world_rank() == 0)
    std::printf("  observed order in space: %.3f (finest pair), %.3f (fit)\n", q, order(hs, errs));
  return q;
}

// fixed 16^3 grid, dt halved: the difference to a run with dt / 16 measures
// the time error alone
double time_order(const std::string& scheme) {
  const double t_end = 0.64;
  auto run = [&](int steps) {
    Config c = mms_case(16, 16, 16, scheme);
    auto s = std::make_unique<FlowSolver>(c, MPI_COMM_WORLD);
    s->initialize();
    for (int n = 0; n < steps; ++n) s->advance(t_end / steps);
    return s;
  };
  auto ref = run(256);
  std::vector<double> dts, errs;
  for (int steps : {16, 32, 64}) {
    auto s = run(steps);
    double e = 0;
    const Range3 r = s->grid().interior();
    for (Field3 FlowState::*f : {&FlowState::u, &FlowState::v, &FlowState::w})
      e = std::max(e, max_diff(s->state().*f, ref->state().*f, r));
    e = global_max(e);
    dts.push_back(t_end / steps);
    errs.push_back(e);
    if (world_rank() == 0)
      std::printf("  %s, dt = %.4f  difference to dt/16: %.3e\n", scheme.c_str(), dts.back(), e);
  }
  const double q = order(dts, errs);
  if (world_rank() == 0) std::printf("  observed order in time: %.3f\n", q);
  return q;
}

}  // namespace

TEST(Manufactured, SecondOrderInSpace) {
  const double q = space_order("explicit");
  EXPECT_GT(q, 1.9);
  EXPECT_LT(q, 2.2);
}

TEST(Manufactured, OrderInTime) {
  // RK3 with the forcing at the stage times and a projection every stage:
  // third order for the velocity here (no time-dependent boundary data)
  EXPECT_GT(time_order("explicit"), 2.8);
}

TEST(Manufactured, ImplicitViscositySecondOrderInSpace) {
  const double q = space_order("implicit");
  EXPECT_GT(q, 1.9);
  EXPECT_LT(q, 2.2);
}

TEST(Manufactured, ImplicitViscositySecondOrderInTime) {
  // Crank-Nicolson across the stages: second order (Rai & Moin; CaNS)
  const double q = time_order("implicit");
  EXPECT_GT(q, 1.9);
  EXPECT_LT(q, 2.3);
}
