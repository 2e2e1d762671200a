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

// The GPU loop (for_block below): i fastest, so x-pencils and the buffers are
// written (or read) contiguously; 4-D, so no element pays for index divisions.
using Policy4 =
    Kokkos::MDRangePolicy<ExecSpace, Kokkos::Rank<4, Kokkos::Iterate::Left, Kokkos::Iterate::Left>>;

// Runs body(q, i, jj, k) over a block's index space. GPUs: the 4-D MDRange,
// i fastest across the threads. Host: 16 x 8 x 8 blocks of (i, jj, k) per
// parallel iteration, so the cache lines of both the source and the
// destination are used whole, within L1, whichever of i, jj, k is contiguous
// in them.
template <class Body>
void for_block(const char* label, const PencilBlock& b, int p, const Body& body) {
  if constexpr (host_lines) {
    constexpr int t = 8, ti_len = 16;
    const int nyb = b.nyb, nzl = b.nzl, nxl = b.nxl;
    const int tj = (nyb + t - 1) / t, tk = (nzl + t - 1) / t, ti = (nxl + ti_len - 1) / ti_len;
    const long nblocks = long(ti) * tj * tk * p;
    Kokkos::parallel_for(label, Kokkos::RangePolicy<ExecSpace>(0, nblocks), [=](long l) {
      const int bi = int(l % ti) * ti_len, bj = int(l / ti % tj) * t, bk = int(l / (long(ti) * tj) % tk) * t;
      const int q = int(l / (long(ti) * tj * tk));
      const int ie = bi + ti_len < nxl ? bi + ti_len : nxl;
      const int je = bj + t < nyb ? bj + t : nyb, ke = bk + t < nzl ? bk + t : nzl;
      for (int k = bk; k < ke; ++k)
        for (int jj = bj; jj < je; ++jj)
          for (int i = bi; i < ie; ++i) body(q, i, jj, k);
    });
  } else {
    Kokkos::parallel_for(
        label, Policy4({0, 0, 0, 0}, {b.nxl, b.nyb, b.nzl, p}),
        KOKKOS_LAMBDA(int i, int jj, int k, int q) { body(q, i, jj, k); });
  }
}

// Moves one pencil orientation into another among the p ranks of `comm`:
// element from(q, i, jj, k) of src goes to element to(q', i, jj, k) of dst on
// peer q, where q' = me is this rank's place in comm. With p = 1 it is a
// local permutation and MPI is skipped; otherwise this rank's own block is
// copied straight from src to dst inside the pack kernel and left out of the
// all-to-all (counts of g.counts: 0 for me). Adds the bytes sent to other
// ranks to `sent`.
template <class From, class To>
void move(const char* pack_label, const char* unpack_label, const Array1& src, const Array1& dst,
          MpiBuffer& send, MpiBuffer& recv, const TransposeGroup& g, const PencilBlock& b, From from, To to,
          size_t& sent) {
  Kokkos::Profiling::ScopedRegion region("transpose");
  const int p = g.p, me = g.me;
  if (p == 1) {
    for_block(
        pack_label, b, 1,
        KOKKOS_LAMBDA(int, int i, int jj, int k) { dst(to(0, i, jj, k)) = src(from(0, i, jj, k)); });
    return;
  }
  auto s = send.dev;
  for_block(
      pack_label, b, p, KOKKOS_LAMBDA(int q, int i, int jj, int k) {
        if (q == me)
          dst(to(me, i, jj, k)) = src(from(me, i, jj, k));
        else
          s(b.flat(q, i, jj, k)) = src(from(q, i, jj, k));
      });
  sent += size_t(p - 1) * b.block() * sizeof(Real);
  MPI_Alltoallv(send.send_ptr(), g.counts.data(), g.displs.data(), MPI_DOUBLE, recv.recv_ptr(),
                g.counts.data(), g.displs.data(), MPI_DOUBLE, g.comm);
  recv.received();
  auto r = recv.dev;
  for_block(
      unpack_label, b, p, KOKKOS_LAMBDA(int q, int i, int jj, int k) {
        if (q != me) dst(to(q, i, jj, k)) = r(b.flat(q, i, jj, k));
      });
}

}  // namespace

TransposeGroup::TransposeGroup(MPI_Comm c, int np, int rank, long block) : comm(c), p(np), me(rank) {
  for (int q = 0; q < p; ++q) {
    counts.push_back(q == me ? 0 : int(block));
    displs.push_back(int(q * block));
  }
}

Transposer::Transposer(const Decomposition& dec)
    : dec_(dec),
      xgroup_(dec.xcomm, dec.px, dec.ix, long(dec.nxl) * dec.ny_x * dec.nzl),
      zgroup_(dec.zcomm, dec.pz, dec.kz, long(dec.nxl) * dec.ny_z * dec.nzl) {
  send_ = MpiBuffer("transpose_send", y_size());
  recv_ = MpiBuffer("transpose_recv", y_size());
}

void Transposer::y_to_x(const Array1& y, const Array1& x) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_x, dec_.nzl, dec_.nx};
  move(
      "transpose_pack_y_to_x", "transpose_unpack_y_to_x", y, x, send_, recv_, xgroup_, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.x(q, i, jj, k); }, bytes_sent_);
}

void Transposer::x_to_y(const Array1& x, const Array1& y) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_x, dec_.nzl, dec_.nx};
  move(
      "transpose_pack_x_to_y", "transpose_unpack_x_to_y", x, y, send_, recv_, xgroup_, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.x(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); }, bytes_sent_);
}

void Transposer::y_to_z(const Array1& y, const Array1& z) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_z, dec_.nzl, dec_.nz};
  move(
      "transpose_pack_y_to_z", "transpose_unpack_y_to_z", y, z, send_, recv_, zgroup_, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.z(q, i, jj, k); }, bytes_sent_);
}

void Transposer::z_to_y(const Array1& z, const Array1& y) {
  const PencilBlock b{dec_.ny, dec_.nxl, dec_.ny_z, dec_.nzl, dec_.nz};
  move(
      "transpose_pack_z_to_y", "transpose_unpack_z_to_y", z, y, send_, recv_, zgroup_, b,
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.z(q, i, jj, k); },
      KOKKOS_LAMBDA(int q, int i, int jj, int k) { return b.y(q, i, jj, k); }, bytes_sent_);
}

}  // namespace softflow
