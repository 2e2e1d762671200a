// The part of the grid the solid phase can reach within one step, so that a
// dilute case pays for phi and B only around its particles, not over the box.
//
// Why a margin of 9 cells per step: a cell's transport right-hand side
// depends only on the cells within 3 of it along the axes (WENO5's stencil),
// and phi's redistribution keeps zeros at zero, so the support of phi (and of
// B - I, which vanishes where phi < phi_fluid_cut) grows by at most 3 cells
// per RK3 stage, whatever the time step. Outside that region phi stays
// exactly 0 and B exactly I, so skipping it changes nothing but the order of
// floating-point sums. The elastic force reaches one cell further (edge and
// face averages).
#pragma once
#include "../src/grid.hpp"

namespace softflow {

constexpr int solid_region_margin = 3 * 3;  // 3 cells per stage, 3 stages

// Inclusive storage-index bounds of the cells where phi != 0 (lo > hi: none).
struct IndexBox {
  int lo[3], hi[3];
};

// Kokkos reducer for the union of boxes.
struct BoxUnion {
  using reducer = BoxUnion;
  using value_type = IndexBox;
  using result_view_type = Kokkos::View<value_type, Kokkos::HostSpace, Kokkos::MemoryUnmanaged>;
  value_type& value;
  KOKKOS_INLINE_FUNCTION explicit BoxUnion(value_type& v) : value(v) {}
  KOKKOS_INLINE_FUNCTION void join(value_type& dst, const value_type& src) const {
    for (int d = 0; d < 3; ++d) {
      dst.lo[d] = src.lo[d] < dst.lo[d] ? src.lo[d] : dst.lo[d];
      dst.hi[d] = src.hi[d] > dst.hi[d] ? src.hi[d] : dst.hi[d];
    }
  }
  KOKKOS_INLINE_FUNCTION void init(value_type& v) const {
    for (int d = 0; d < 3; ++d) {
      v.lo[d] = 1 << 30;
      v.hi[d] = -(1 << 30);
    }
  }
  KOKKOS_INLINE_FUNCTION value_type& reference() const { return value; }
  KOKKOS_INLINE_FUNCTION result_view_type view() const { return result_view_type(&value); }
  KOKKOS_INLINE_FUNCTION bool references_scalar() const { return true; }
};

// The box of phi's support over the whole storage, ghosts included: phi in a
// neighbour's (or the periodic image's) cells within 3 of this rank's
// interior reaches the interior this stage.
inline IndexBox phi_support(const Grid& g, const Field3& phi) {
  IndexBox box;
  par_reduce(
      "solid_support_box", g.all(),
      KOKKOS_LAMBDA(int i, int j, int k, IndexBox& b) {
        if (phi(i, j, k) == 0) return;
        const int c[3] = {i, j, k};
        for (int d = 0; d < 3; ++d) {
          b.lo[d] = c[d] < b.lo[d] ? c[d] : b.lo[d];
          b.hi[d] = c[d] > b.hi[d] ? c[d] : b.hi[d];
        }
      },
      BoxUnion(box));
  return box;
}

// The box grown by m cells on every side, as a range clipped to `within`
// (empty when the box is).
inline Range3 grown_range(const IndexBox& b, int m, const Range3& within) {
  const Range3 none{within.ib, within.ib, within.jb, within.jb, within.kb, within.kb};
  if (b.lo[0] > b.hi[0]) return none;
  const Range3 r = grown({b.lo[0], b.hi[0] + 1, b.lo[1], b.hi[1] + 1, b.lo[2], b.hi[2] + 1}, m, within);
  return r.empty() ? none : r;
}

}  // namespace softflow
