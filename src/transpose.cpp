#include "transpose.hpp"

namespace softflow {

Transposer::Transposer(const Decomposition& dec) : dec_(dec) {
  send_ = MpiBuffer("transpose_send", y_size());
  recv_ = MpiBuffer("transpose_recv", y_size());
}

void Transposer::alltoall(MPI_Comm comm, int p, size_t n) {
  const int blk = int(n / p);
  MPI_Alltoall(send_.send_ptr(), blk, MPI_DOUBLE, recv_.recv_ptr(), blk, MPI_DOUBLE, comm);
  recv_.received();
}

// Block for peer q (y <-> x): i < nxl, jj < ny_x, k < nzl, flat m = i + nxl*(jj + ny_x*k).
void Transposer::y_to_x(const Array1& y, const Array1& x) {
  const int ny = dec_.ny, nx = dec_.nx, nxl = dec_.nxl, nyx = dec_.ny_x, nzl = dec_.nzl;
  const int p = dec_.px;
  const long blk = long(nxl) * nyx * nzl;
  if (p == 1) {
    Kokkos::parallel_for("transpose_y_to_x", Kokkos::RangePolicy<ExecSpace>(0, blk),
                         KOKKOS_LAMBDA(long m) {
                           const int i = m % nx, j = (m / nx) % ny, k = m / (long(nx) * ny);
                           x(m) = y(j + ny * (i + long(nxl) * k));
                         });
    return;
  }
  auto s = send_.dev;
  Kokkos::parallel_for("transpose_pack_y_to_x", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyx, k = m / (long(nxl) * nyx);
                         s(t) = y(q * nyx + jj + ny * (i + long(nxl) * k));
                       });
  alltoall(dec_.xcomm, p, p * blk);
  auto r = recv_.dev;
  Kokkos::parallel_for("transpose_unpack_y_to_x", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyx, k = m / (long(nxl) * nyx);
                         x(q * nxl + i + nx * (jj + long(nyx) * k)) = r(t);
                       });
}

void Transposer::x_to_y(const Array1& x, const Array1& y) {
  const int ny = dec_.ny, nx = dec_.nx, nxl = dec_.nxl, nyx = dec_.ny_x, nzl = dec_.nzl;
  const int p = dec_.px;
  const long blk = long(nxl) * nyx * nzl;
  if (p == 1) {
    Kokkos::parallel_for("transpose_x_to_y", Kokkos::RangePolicy<ExecSpace>(0, blk),
                         KOKKOS_LAMBDA(long m) {
                           const int j = m % ny, i = (m / ny) % nx, k = m / (long(nx) * ny);
                           y(m) = x(i + nx * (j + long(ny) * k));
                         });
    return;
  }
  auto s = send_.dev;
  Kokkos::parallel_for("transpose_pack_x_to_y", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyx, k = m / (long(nxl) * nyx);
                         s(t) = x(q * nxl + i + nx * (jj + long(nyx) * k));
                       });
  alltoall(dec_.xcomm, p, p * blk);
  auto r = recv_.dev;
  Kokkos::parallel_for("transpose_unpack_x_to_y", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyx, k = m / (long(nxl) * nyx);
                         y(q * nyx + jj + ny * (i + long(nxl) * k)) = r(t);
                       });
}

// Block for peer q (y <-> z): i < nxl, jj < ny_z, k < nzl, flat m = i + nxl*(jj + ny_z*k).
void Transposer::y_to_z(const Array1& y, const Array1& z) {
  const int ny = dec_.ny, nz = dec_.nz, nxl = dec_.nxl, nyz = dec_.ny_z, nzl = dec_.nzl;
  const int p = dec_.pz;
  const long blk = long(nxl) * nyz * nzl;
  if (p == 1) {
    Kokkos::parallel_for("transpose_y_to_z", Kokkos::RangePolicy<ExecSpace>(0, blk),
                         KOKKOS_LAMBDA(long m) {
                           const int k = m % nz, i = (m / nz) % nxl, j = m / (long(nz) * nxl);
                           z(m) = y(j + ny * (i + long(nxl) * k));
                         });
    return;
  }
  auto s = send_.dev;
  Kokkos::parallel_for("transpose_pack_y_to_z", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyz, k = m / (long(nxl) * nyz);
                         s(t) = y(q * nyz + jj + ny * (i + long(nxl) * k));
                       });
  alltoall(dec_.zcomm, p, p * blk);
  auto r = recv_.dev;
  Kokkos::parallel_for("transpose_unpack_y_to_z", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyz, k = m / (long(nxl) * nyz);
                         z(q * nzl + k + nz * (i + long(nxl) * jj)) = r(t);
                       });
}

void Transposer::z_to_y(const Array1& z, const Array1& y) {
  const int ny = dec_.ny, nz = dec_.nz, nxl = dec_.nxl, nyz = dec_.ny_z, nzl = dec_.nzl;
  const int p = dec_.pz;
  const long blk = long(nxl) * nyz * nzl;
  if (p == 1) {
    Kokkos::parallel_for("transpose_z_to_y", Kokkos::RangePolicy<ExecSpace>(0, blk),
                         KOKKOS_LAMBDA(long m) {
                           const int j = m % ny, i = (m / ny) % nxl, k = m / (long(ny) * nxl);
                           y(m) = z(k + nz * (i + long(nxl) * j));
                         });
    return;
  }
  auto s = send_.dev;
  Kokkos::parallel_for("transpose_pack_z_to_y", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyz, k = m / (long(nxl) * nyz);
                         s(t) = z(q * nzl + k + nz * (i + long(nxl) * jj));
                       });
  alltoall(dec_.zcomm, p, p * blk);
  auto r = recv_.dev;
  Kokkos::parallel_for("transpose_unpack_z_to_y", Kokkos::RangePolicy<ExecSpace>(0, p * blk),
                       KOKKOS_LAMBDA(long t) {
                         const int q = t / blk;
                         const long m = t % blk;
                         const int i = m % nxl, jj = (m / nxl) % nyz, k = m / (long(nxl) * nyz);
                         y(q * nyz + jj + ny * (i + long(nxl) * k)) = r(t);
                       });
}

}  // namespace softflow
