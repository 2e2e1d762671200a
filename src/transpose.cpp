#include "transpose.hpp"

namespace softflow {

namespace {

// Moves one pencil orientation into another among the p ranks of `comm`:
// element from(q, m) of src goes to element to(q', m) of dst on peer q, where
// q' is this rank's place in comm, for every flat block index m < blk. With
// p = 1 it is a local permutation and MPI is skipped.
template <class From, class To>
void move(const char* pack_label, const char* unpack_label, const Array1& src, const Array1& dst,
          MpiBuffer& send, MpiBuffer& recv, MPI_Comm comm, int p, long blk, From from, To to) {
  using Range = Kokkos::RangePolicy<ExecSpace>;
  if (p == 1) {
    Kokkos::parallel_for(pack_label, Range(0, blk), KOKKOS_LAMBDA(long m) { dst(to(0, m)) = src(from(0, m)); });
    return;
  }
  auto s = send.dev;
  Kokkos::parallel_for(pack_label, Range(0, p * blk), KOKKOS_LAMBDA(long t) { s(t) = src(from(int(t / blk), t % blk)); });
  MPI_Alltoall(send.send_ptr(), int(blk), MPI_DOUBLE, recv.recv_ptr(), int(blk), MPI_DOUBLE, comm);
  recv.received();
  auto r = recv.dev;
  Kokkos::parallel_for(unpack_label, Range(0, p * blk), KOKKOS_LAMBDA(long t) { dst(to(int(t / blk), t % blk)) = r(t); });
}

}  // namespace

Transposer::Transposer(const Decomposition& dec) : dec_(dec) {
  send_ = MpiBuffer("transpose_send", y_size());
  recv_ = MpiBuffer("transpose_recv", y_size());
}

// The block exchanged with peer q: i < nxl, jj < nyb, k < nzl, flat
// m = i + nxl * (jj + nyb * k), where nyb is the y rows each peer holds in
// the target pencil (ny_x inside xcomm, ny_z inside zcomm). Its place in the
// y-pencil is row q * nyb + jj, in the x-pencil column q * nxl + i, in the
// z-pencil line q * nzl + k.
struct PencilBlock {
  int ny, nxl, nyb, nzl, n_other;  // n_other: nx for x-pencils, nz for z-pencils
  struct Index {
    int i, jj;
    long k;
  };
  KOKKOS_INLINE_FUNCTION Index at(long m) const {
    return {int(m % nxl), int((m / nxl) % nyb), m / (long(nxl) * nyb)};
  }
  KOKKOS_INLINE_FUNCTION long y(int q, long m) const {
    const Index a = at(m);
    return q * nyb + a.jj + ny * (a.i + nxl * a.k);
  }
  KOKKOS_INLINE_FUNCTION long x(int q, long m) const {
    const Index a = at(m);
    return q * nxl + a.i + n_other * (a.jj + nyb * a.k);
  }
  KOKKOS_INLINE_FUNCTION long z(int q, long m) const {
    const Index a = at(m);
    return q * nzl + a.k + n_other * (a.i + long(nxl) * a.jj);
  }
};

void Transposer::y_to_x(const Array1& y, const Array1& x) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_x, dec_.nzl, dec_.nx};
  move("transpose_pack_y_to_x", "transpose_unpack_y_to_x", y, x, send_, recv_, dec_.xcomm, dec_.px,
       long(dec_.nxl) * dec_.ny_x * dec_.nzl, KOKKOS_LAMBDA(int q, long m) { return b.y(q, m); },
       KOKKOS_LAMBDA(int q, long m) { return b.x(q, m); });
}

void Transposer::x_to_y(const Array1& x, const Array1& y) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_x, dec_.nzl, dec_.nx};
  move("transpose_pack_x_to_y", "transpose_unpack_x_to_y", x, y, send_, recv_, dec_.xcomm, dec_.px,
       long(dec_.nxl) * dec_.ny_x * dec_.nzl, KOKKOS_LAMBDA(int q, long m) { return b.x(q, m); },
       KOKKOS_LAMBDA(int q, long m) { return b.y(q, m); });
}

void Transposer::y_to_z(const Array1& y, const Array1& z) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_z, dec_.nzl, dec_.nz};
  move("transpose_pack_y_to_z", "transpose_unpack_y_to_z", y, z, send_, recv_, dec_.zcomm, dec_.pz,
       long(dec_.nxl) * dec_.ny_z * dec_.nzl, KOKKOS_LAMBDA(int q, long m) { return b.y(q, m); },
       KOKKOS_LAMBDA(int q, long m) { return b.z(q, m); });
}

void Transposer::z_to_y(const Array1& z, const Array1& y) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_z, dec_.nzl, dec_.nz};
  move("transpose_pack_z_to_y", "transpose_unpack_z_to_y", z, y, send_, recv_, dec_.zcomm, dec_.pz,
       long(dec_.nxl) * dec_.ny_z * dec_.nzl, KOKKOS_LAMBDA(int q, long m) { return b.z(q, m); },
       KOKKOS_LAMBDA(int q, long m) { return b.y(q, m); });
}

}  // namespace softflow
