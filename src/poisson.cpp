#include "poisson.hpp"

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

void PoissonSolver::solve() {
  tr_.y_to_x(y_, x_);
  fft_x_.forward();
  tr_.x_to_y(x_, y_);
  tr_.y_to_z(y_, z_);
  fft_z_.forward();
  tr_.z_to_y(z_, y_);
  tridiagonal();
  tr_.y_to_z(y_, z_);
  fft_z_.backward();
  tr_.z_to_y(z_, y_);
  tr_.y_to_x(y_, x_);
  fft_x_.backward();
  tr_.x_to_y(x_, y_);
}

// One Thomas sweep per (kx, kz) line; the 1/(nx nz) of the two unnormalised
// backward FFTs is folded into the right-hand side here.
void PoissonSolver::tridiagonal() {
  const int ny = g_.ny, nxl = dec_.nxl, x0 = dec_.x0, z0 = dec_.z0;
  const Real idy2 = 1 / (g_.dy * g_.dy);
  const Real scale = Real(1) / (Real(g_.nx) * g_.nz);
  auto y = y_, cp = scratch_, lamx = lamx_, lamz = lamz_;
  const long lines = long(dec_.nxl) * dec_.nzl;
  Kokkos::parallel_for(
      "poisson_tridiagonal", Kokkos::RangePolicy<ExecSpace>(0, lines), KOKKOS_LAMBDA(long l) {
        const int i = l % nxl, k = l / nxl;
        const bool singular = (x0 + i == 0) && (z0 + k == 0);
        const Real lam = lamx(x0 + i) + lamz(z0 + k);
        const long b0 = l * ny;
        // row j: idy2 p[j-1] + (diag_j + lam) p[j] + idy2 p[j+1] = r[j]
        auto diag = [&](int j) {
          return (j == 0 || j == ny - 1 ? -idy2 : -2 * idy2) + lam;
        };
        Real b = singular ? Real(1) : diag(0);
        Real c = singular ? Real(0) : idy2;
        Real d = singular ? Real(0) : y(b0) * scale;
        cp(b0) = c / b;
        y(b0) = d / b;
        for (int j = 1; j < ny; ++j) {
          const Real cj = j < ny - 1 ? idy2 : Real(0);
          const Real den = diag(j) - idy2 * cp(b0 + j - 1);
          cp(b0 + j) = cj / den;
          y(b0 + j) = (y(b0 + j) * scale - idy2 * y(b0 + j - 1)) / den;
        }
        for (int j = ny - 2; j >= 0; --j) y(b0 + j) -= cp(b0 + j) * y(b0 + j + 1);
      });
}

}  // namespace softflow
