#include "poisson.hpp"

#include <Kokkos_Profiling_ScopedRegion.hpp>

#include <cmath>

namespace softflow {

namespace {
Array1 eigenvalues(const char* label, int n, Real d) {
  Array1 lam(std::string(label), n);
  auto h = Kokkos::create_mirror_view(lam);
  for (int m = 0; m < n; ++m) {
    const int k = LineFft::wavenumber(m, n);
    h(m) = (2 * std::cos(2 * M_PI * k / n) - 2) / (d * d);
  }
  Kokkos::deep_copy(lam, h);
  return lam;
}
}  // namespace

PoissonSolver::PoissonSolver(const Decomposition& dec, const Grid& g)
    : dec_(dec),
      g_(g),
      tr_(dec),
      y_("poisson_y", tr_.y_size()),
      x_("poisson_x", tr_.x_size()),
      z_("poisson_z", tr_.z_size()),
      scratch_("poisson_scratch", tr_.y_size()),
      lamx_(eigenvalues("poisson_lamx", g.nx, g.dx)),
      lamz_(eigenvalues("poisson_lamz", g.nz, g.dz)),
      fft_x_(g.nx, long(dec.ny_x) * dec.nzl, x_),
      fft_z_(g.nz, long(dec.nxl) * dec.ny_z, z_) {}

void PoissonSolver::solve(const Array1& y, const LineOperator& op) {
  // regions name the parts for the perf harness (perf/kernel_timer.hpp)
  Kokkos::Profiling::ScopedRegion region("poisson_solve");
  auto fft = [](LineFft& f, bool forward) {
    Kokkos::Profiling::ScopedRegion r("fft");
    forward ? f.forward() : f.backward();
  };
  tr_.y_to_x(y, x_);
  fft(fft_x_, true);
  tr_.x_to_y(x_, y);
  tr_.y_to_z(y, z_);
  fft(fft_z_, true);
  tr_.z_to_y(z_, y);
  tridiagonal(y, op);
  tr_.y_to_z(y, z_);
  fft(fft_z_, false);
  tr_.z_to_y(z_, y);
  tr_.y_to_x(y, x_);
  fft(fft_x_, false);
  tr_.x_to_y(x_, y);
}

// One Thomas sweep per (kx, kz) line; the 1/(nx nz) of the two unnormalised
// backward FFTs is folded into the right-hand side here. Row j reads
//   lo_j x[j-1] + (identity + laplacian (lam + dyy_j)) x[j] + up_j x[j+1] = r[j]
// with lo = up = laplacian / dy^2 and dyy_j the y part of the diagonal.
void PoissonSolver::tridiagonal(const Array1& y, const LineOperator& op) {
  const int ny = g_.ny, nxl = dec_.nxl, x0 = dec_.x0, z0 = dec_.z0;
  const Real idy2 = 1 / (g_.dy * g_.dy);
  const Real scale = Real(1) / (Real(g_.nx) * g_.nz);
  const Real id = op.identity, lap = op.laplacian, off = lap * idy2;
  const WallRows walls = op.walls;
  // only the pure Neumann Laplacian is singular (constant mode)
  const bool pin = walls == WallRows::neumann && id == 0;
  auto cp = scratch_, lamx = lamx_, lamz = lamz_;
  const long lines = long(dec_.nxl) * dec_.nzl;
  Kokkos::parallel_for(
      "poisson_tridiagonal", Kokkos::RangePolicy<ExecSpace>(0, lines), KOKKOS_LAMBDA(long l) {
        const int i = l % nxl, k = l / nxl;
        const bool singular = pin && (x0 + i == 0) && (z0 + k == 0);
        const Real lam = lamx(x0 + i) + lamz(z0 + k);
        const long b0 = l * ny;
        const bool face = walls == WallRows::dirichlet_face;
        auto dyy = [&](int j) {
          if (j == 0 || j == ny - 1) {
            if (walls == WallRows::neumann) return -idy2;
            if (walls == WallRows::dirichlet_centre) return -3 * idy2;
          }
          return -2 * idy2;
        };
        auto diag = [&](int j) { return (face && j == ny - 1) ? Real(1) : id + lap * (lam + dyy(j)); };
        auto lower = [&](int j) { return (face && j == ny - 1) ? Real(0) : off; };
        auto upper = [&](int j) { return (j == ny - 1 || (face && j == ny - 2)) ? Real(0) : off; };
        auto rhs = [&](int j) { return (face && j == ny - 1) ? Real(0) : y(b0 + j) * scale; };
        const Real b = singular ? Real(1) : diag(0);
        cp(b0) = singular ? Real(0) : upper(0) / b;
        y(b0) = singular ? Real(0) : rhs(0) / b;
        for (int j = 1; j < ny; ++j) {
          const Real den = diag(j) - lower(j) * cp(b0 + j - 1);
          cp(b0 + j) = upper(j) / den;
          y(b0 + j) = (rhs(j) - lower(j) * y(b0 + j - 1)) / den;
        }
        for (int j = ny - 2; j >= 0; --j) y(b0 + j) -= cp(b0 + j) * y(b0 + j + 1);
      });
}

}  // namespace softflow
