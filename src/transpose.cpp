#include "transpose.hpp"

#include <Kokkos_Profiling_ScopedRegion.hpp>

namespace softflow {

namespace {

// The block exchanged with peer q: i < nxl, jj < nyb, k < nzl, where nyb is
// the y rows each peer holds in the target pencil (ny_x inside xcomm, ny_z
// inside zcomm). Its place in the y-pencil is row q * nyb + jj, in the
// x-pencil column q * nxl + i, in the z-pencil line q * nzl + k. In the
// message buffers it is the flat q * blk + i + nxl * (jj + nyb * k).
struct PencilBlock {
  int ny, nxl, nyb, nzl, n_other;  // n_other: nx for x-pencils, nz for z-pencils
  KOKKOS_INLINE_FUNCTION long y(int q, int i, int jj, int k) const {
    return q * nyb + jj + long(ny) * (i + long(nxl) * k);
  }
  KOKKOS_INLINE_FUNCTION long x(int q, int i, int jj, int k) const {
    return q * nxl + i + long(n_other) * (jj + long(nyb) * k);
  }
  KOKKOS_INLINE_FUNCTION long z(int q, int i, int jj, int k) const {
    return q * nzl + k + long(n_other) * (i + long(nxl) * jj);
  }
  KOKKOS_INLINE_FUNCTION long flat(int q, int i, int jj, int k) const {
    return i + long(nxl) * (jj + long(nyb) * (k + long(nzl) * q));
  }
  long block() const { return long(nxl) * nyb * nzl; }
};

// i fastest: x-pencils and the buffers are written (or read) contiguously.
// A 4-D loop, so no element pays for index divisions (a flat loop did).
using Policy4 =
    Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<4, Kokkos::Iterate::Left, Kokkos::Iterate::Left>>;

// Moves one pencil orientation into another among the p ranks of `comm`:
// element from(q, i, jj, k) of src goes to element to(q', i, jj, k) of dst on
// peer q, where q' is this rank's place in comm. With p = 1 it is a local
// permutation and MPI is skipped. Adds the bytes sent to other ranks to `sent`.
template <class From, class To>
void move(const char* pack_label, const char* unpack_label, const Array1& src, const Array1& dst,
          MpiBuffer& send, MpiBuffer& recv, MPI_Comm comm, int p, const PencilBlock& b, From from, To to,
          size_t& sent) {
  Kokkos::Profiling::ScopedRegion region("transpose");
  const Policy4 all({0, 0, 0, 0}, {b.nxl, b.nyb, b.nzl, p});
  if (p == 1) {
    Kokkos::parallel_for(
        pack_label, all,
        KOKKOS_LAMBDA(int i, int jj, int k, int) { dst(to(0, i, jj, k)) = src(from(0, i, jj, k)); });
    return;
  }
  auto s = send.dev;
  Kokkos::parallel_for(
      pack_label, all,
      KOKKOS_LAMBDA(int i, int jj, int k, int q) { s(b.flat(q, i, jj, k)) = src(from(q, i, jj, k)); });
  const long blk = b.block();
  sent += size_t(p - 1) * blk * sizeof(Real);
  MPI_Alltoall(send.send_ptr(), int(blk), MPI_DOUBLE, recv.recv_ptr(), int(blk), MPI_DOUBLE, comm);
  recv.received();
  auto r = recv.dev;
  Kokkos::parallel_for(
      unpack_label, all,
      KOKKOS_LAMBDA(int i, int jj, int k, int q) { dst(to(q, i, jj, k)) = r(b.flat(q, i, jj, k)); });
}

}  // namespace

Transposer::Transposer(const Decomposition& dec) : dec_(dec) {
  send_ = MpiBuffer("transpose_send", y_size());
  recv_ = MpiBuffer("transpose_recv", y_size());
}

void Transposer::y_to_x(const Array1& y, const Array1& x) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_x, dec_.nzl, dec_.nx};
  move(
      "transpose_pack_y_to_x", "transpose_unpack_y_to_x", y, x, send_, recv_, dec_.xcomm, dec_.px, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.x(q, i, jj, k); }, bytes_sent_);
}

void Transposer::x_to_y(const Array1& x, const Array1& y) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_x, dec_.nzl, dec_.nx};
  move(
      "transpose_pack_x_to_y", "transpose_unpack_x_to_y", x, y, send_, recv_, dec_.xcomm, dec_.px, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.x(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); }, bytes_sent_);
}

void Transposer::y_to_z(const Array1& y, const Array1& z) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_z, dec_.nzl, dec_.nz};
  move(
      "transpose_pack_y_to_z", "transpose_unpack_y_to_z", y, z, send_, recv_, dec_.zcomm, dec_.pz, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.z(q, i, jj, k); }, bytes_sent_);
}

void Transposer::z_to_y(const Array1& z, const Array1& y) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_z, dec_.nzl, dec_.nz};
  move(
      "transpose_pack_z_to_y", "transpose_unpack_z_to_y", z, y, send_, recv_, dec_.zcomm, dec_.pz, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.z(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); }, bytes_sent_);
}

}  // namespace softflow
