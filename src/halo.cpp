#include "halo.hpp"

#include <Kokkos_Profiling_ScopedRegion.hpp>

#include <algorithm>
#include <stdexcept>

namespace softflow {

Halo::Halo(const Decomposition& dec, const Grid& g) : dec_(dec), g_(g) {
  left_x_ = (dec.ix - 1 + dec.px) % dec.px;
  right_x_ = (dec.ix + 1) % dec.px;
  left_z_ = (dec.kz - 1 + dec.pz) % dec.pz;
  right_z_ = (dec.kz + 1) % dec.pz;
  size_t n = max_fields * size_t(Grid::ng) * g.sy() * std::max(g.nzl, g.sx());
  send_lo_ = MpiBuffer("halo_send_lo", n);
  send_hi_ = MpiBuffer("halo_send_hi", n);
  recv_lo_ = MpiBuffer("halo_recv_lo", n);
  recv_hi_ = MpiBuffer("halo_recv_hi", n);
}

size_t Halo::bytes_per_field() const {
  const size_t ng = Grid::ng;
  return sizeof(Real) * 2 * ng * g_.sy() * ((dec_.px > 1 ? g_.nzl : 0) + (dec_.pz > 1 ? g_.sx() : 0));
}

void Halo::exchange(std::initializer_list<Field3> fields) {
  if (fields.size() > size_t(max_fields)) throw std::logic_error("Halo::exchange: too many fields");
  Field3 f[max_fields];
  int nf = 0;
  for (const auto& x : fields) f[nf++] = x;
  exchange(f, nf);
}

void Halo::exchange(const Field3* f, int nf) {
  if (nf > max_fields) throw std::logic_error("Halo::exchange: too many fields");
  Kokkos::Profiling::ScopedRegion region("halo_exchange");
  exchange_dir(0, f, nf);
  exchange_dir(2, f, nf);
}

// dir 0: x, slabs i in [ng, 2ng) and [n, n+ng) over j all, k interior.
// dir 2: z, slabs k likewise over i all, j all.
void Halo::exchange_dir(int dir, const Field3* f, int nf) {
  const int ng = Grid::ng;
  const Grid g = g_;
  const int n = dir == 0 ? g.nxl : g.nzl;
  const int p = dir == 0 ? dec_.px : dec_.pz;
  // slab extents (a: the exchanged direction, b = j, c: the other direction)
  const int nb = g.sy();
  const int nc = dir == 0 ? g.nzl : g.sx();
  const int c0 = dir == 0 ? ng : 0;
  const long slab = long(ng) * nb * nc;

  if (p == 1) {
    // periodic copy on this rank
    for (int m = 0; m < nf; ++m) {
      Field3 a = f[m];
      Range3 r = dir == 0 ? Range3{0, ng, 0, nb, c0, c0 + nc} : Range3{0, nc, 0, nb, 0, ng};
      par_for(
          dir == 0 ? "halo_periodic_x" : "halo_periodic_z", r, KOKKOS_LAMBDA(int i, int j, int k) {
            if (dir == 0) {
              a(i, j, k) = a(i + n, j, k);
              a(i + n + ng, j, k) = a(i + ng, j, k);
            } else {
              a(i, j, k) = a(i, j, k + n);
              a(i, j, k + n + ng) = a(i, j, k + ng);
            }
          });
    }
    return;
  }

  auto slo = send_lo_.dev, shi = send_hi_.dev;
  for (int m = 0; m < nf; ++m) {
    Field3 a = f[m];
    const long off = m * slab;
    Range3 r{0, ng, 0, nb, 0, nc};
    par_for(
        dir == 0 ? "halo_pack_x" : "halo_pack_z", r, KOKKOS_LAMBDA(int s, int j, int c) {
          const long q = off + s + long(ng) * (j + long(nb) * c);
          if (dir == 0) {
            slo(q) = a(ng + s, j, c0 + c);
            shi(q) = a(n + s, j, c0 + c);
          } else {
            slo(q) = a(c, j, ng + s);
            shi(q) = a(c, j, n + s);
          }
        });
  }
  MPI_Comm comm = dir == 0 ? dec_.xcomm : dec_.zcomm;
  int lo = dir == 0 ? left_x_ : left_z_, hi = dir == 0 ? right_x_ : right_z_;
  int count = int(nf * slab);
  bytes_sent_ += 2 * size_t(count) * sizeof(Real);
  MPI_Request req[4];
  MPI_Irecv(recv_lo_.recv_ptr(), count, MPI_DOUBLE, lo, 1, comm, &req[0]);
  MPI_Irecv(recv_hi_.recv_ptr(), count, MPI_DOUBLE, hi, 0, comm, &req[1]);
  MPI_Isend(send_lo_.send_ptr(), count, MPI_DOUBLE, lo, 0, comm, &req[2]);
  MPI_Isend(send_hi_.send_ptr(), count, MPI_DOUBLE, hi, 1, comm, &req[3]);
  MPI_Waitall(4, req, MPI_STATUSES_IGNORE);
  recv_lo_.received();
  recv_hi_.received();
  auto rlo = recv_lo_.dev, rhi = recv_hi_.dev;
  for (int m = 0; m < nf; ++m) {
    Field3 a = f[m];
    const long off = m * slab;
    Range3 r{0, ng, 0, nb, 0, nc};
    par_for(
        dir == 0 ? "halo_unpack_x" : "halo_unpack_z", r, KOKKOS_LAMBDA(int s, int j, int c) {
          const long q = off + s + long(ng) * (j + long(nb) * c);
          // from the low neighbour: its top slab fills my low ghosts; from the high
          // neighbour: its bottom interior slab fills my high ghosts
          if (dir == 0) {
            a(s, j, c0 + c) = rlo(q);
            a(n + ng + s, j, c0 + c) = rhi(q);
          } else {
            a(c, j, s) = rlo(q);
            a(c, j, n + ng + s) = rhi(q);
          }
        });
  }
}

}  // namespace softflow
