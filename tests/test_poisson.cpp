// The Poisson solver inverts the discrete Laplacian of the MAC grid, and the
// projection leaves a velocity field divergence-free to round-off.
#include <gtest/gtest.h>

#include "../kernels/projection.hpp"
#include "../kernels/wall_bc.hpp"
#include "test_util.hpp"

using namespace softflow;
using namespace softflow::test;

namespace {

// Laplacian of p (ghosts set) at interior cell (i, j, k), Neumann walls
// implied by the even-reflection ghosts.
double laplacian_residual(const Grid& g, const Field3& p, const Field3& rhs) {
  const double idx2 = 1 / (g.dx * g.dx), idy2 = 1 / (g.dy * g.dy), idz2 = 1 / (g.dz * g.dz);
  double m = 0;
  par_reduce(
      "test_laplacian_residual", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& x) {
        const double c = p(i, j, k);
        const double l = (p(i + 1, j, k) - 2 * c + p(i - 1, j, k)) * idx2 +
                         (p(i, j + 1, k) - 2 * c + p(i, j - 1, k)) * idy2 +
                         (p(i, j, k + 1) - 2 * c + p(i, j, k - 1)) * idz2;
        const double d = Kokkos::fabs(l - rhs(i, j, k));
        x = d > x ? d : x;
      },
      Kokkos::Max<double>(m));
  return global_max(m);
}

void random_field(const Grid& g, const Field3& f, int seed) {
  const int x0 = g.x0, z0 = g.z0, nx = g.nx, ny = g.ny;
  // a reproducible, decomposition-independent pseudo-random value per global cell
  par_for(
      "test_random", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        unsigned long long s =
            (unsigned long long)(x0 + i - Grid::ng) +
            nx * ((unsigned long long)(j - Grid::ng) + ny * (unsigned long long)(z0 + k - Grid::ng)) +
            1315423911ull * seed;
        s ^= s >> 33;
        s *= 0xff51afd7ed558ccdULL;
        s ^= s >> 33;
        s *= 0xc4ceb9fe1a85ec53ULL;
        s ^= s >> 33;
        f(i, j, k) = double(s >> 11) / double(1ull << 53) - 0.5;
      });
}

}  // namespace

class PoissonTest : public ::testing::TestWithParam<std::array<int, 3>> {};

TEST_P(PoissonTest, InvertsDiscreteLaplacianOfRandomData) {
  auto [nx, ny, nz] = GetParam();
  Config c = couette_case(nx, ny, nz, {"grid.lx=1.3", "grid.lz=0.7"});
  FlowSolver s(c, MPI_COMM_WORLD);
  const Grid g = s.grid();
  Field3 rhs("rhs", g.sx(), g.sy(), g.sz());
  random_field(g, rhs, 7);
  // remove the mean: the Neumann problem is solvable only for zero-mean data
  double sum = 0;
  par_reduce(
      "test_sum", g.interior(), KOKKOS_LAMBDA(int i, int j, int k, double& a) { a += rhs(i, j, k); },
      Kokkos::Sum<double>(sum));
  const double mean = global_sum(sum) / double(g.cells_global());
  double rmax = 0;
  par_reduce(
      "test_sub_mean", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) {
        rhs(i, j, k) -= mean;
        a = Kokkos::fmax(a, Kokkos::fabs(rhs(i, j, k)));
      },
      Kokkos::Max<double>(rmax));
  rmax = global_max(rmax);

  auto y = s.poisson().rhs();
  const int ng = Grid::ng, gny = g.ny, nxl = g.nxl;
  par_for(
      "test_fill", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        y(PoissonSolver::index(i - ng, j - ng, k - ng, gny, nxl)) = rhs(i, j, k);
      });
  s.poisson().solve();
  poisson_to_field(g, y, s.state().p);
  s.fill_pressure_ghosts();
  const double res = laplacian_residual(g, s.state().p, rhs);
  // the residual is relative to the largest term of the operator, |p| / dx^2
  double pmax = 0;
  auto p = s.state().p;
  par_reduce(
      "test_pmax", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) { a = Kokkos::fmax(a, Kokkos::fabs(p(i, j, k))); },
      Kokkos::Max<double>(pmax));
  pmax = global_max(pmax);
  const double scale = std::max(rmax, pmax * 4 * (1 / (g.dx * g.dx) + 1 / (g.dy * g.dy) + 1 / (g.dz * g.dz)));
  EXPECT_LT(res / scale, 1e-12) << "residual " << res << " scale " << scale;
}

INSTANTIATE_TEST_SUITE_P(Grids, PoissonTest,
                         ::testing::Values(std::array<int, 3>{16, 8, 12}, std::array<int, 3>{32, 24, 16},
                                           std::array<int, 3>{12, 36, 20}));

namespace {
// max |div u| and max(|u|, |v|) over the local interior (device loops live
// outside TEST bodies: nvcc forbids extended lambdas in gtest's private TestBody)
void local_div_and_speed(const Grid& g, const FlowState& st, double& div, double& umax) {
  const double idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  auto u = st.u, v = st.v, w = st.w;
  par_reduce(
      "test_div", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) {
        a = Kokkos::fmax(a, Kokkos::fabs(divergence(u, v, w, i, j, k, idx, idy, idz)));
      },
      Kokkos::Max<double>(div));
  par_reduce(
      "test_umax", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, double& a) {
        a = Kokkos::fmax(a, Kokkos::fmax(Kokkos::fabs(u(i, j, k)), Kokkos::fabs(v(i, j, k))));
      },
      Kokkos::Max<double>(umax));
}
}  // namespace

TEST(Projection, LeavesVelocityDivergenceFreeToRoundOff) {
  Config c = couette_case(24, 16, 20, {"grid.lx=2.0", "grid.lz=1.5"});
  FlowSolver s(c, MPI_COMM_WORLD);
  const Grid g = s.grid();
  random_field(g, s.state().u, 1);
  random_field(g, s.state().v, 2);
  random_field(g, s.state().w, 3);
  s.fill_velocity_ghosts();
  divergence_to_poisson(g, s.state(), 1.0, s.poisson().rhs());
  s.poisson().solve();
  poisson_to_field(g, s.poisson().rhs(), s.state().p);
  s.fill_pressure_ghosts();
  correct_velocity(g, s.state(), s.state().p, 1.0);
  s.fill_velocity_ghosts();
  double div = 0, umax = 0;
  local_div_and_speed(g, s.state(), div, umax);
  div = global_max(div);
  umax = global_max(umax);
  const double scaled = div / (umax / std::min({g.dx, g.dy, g.dz}));
  EXPECT_LT(scaled, 1e-12) << "max |div u| = " << div;
  EXPECT_GT(umax, 0.1);  // the projection did not just zero the field
}
