// Which cells have a phi at or above a threshold within `reach` cells (a
// (2 reach + 1)^3 block): the B extension's cells near the solid (reach 2,
// phi >= 1/2) and the transport's live cells for B (reach 1, phi >= 0.05).
// Three separable max passes instead of the block's (2 reach + 1)^3 reads,
// each a plain comparison the compiler vectorises. And the reverse, which
// cells have a phi below a threshold within reach (min passes): the core
// cells whose B the inner band reads (kernels/solid_extension.hpp). Or the
// block's max itself (block_max), which is the mask of every threshold.
#pragma once
#include "../src/types.hpp"

namespace softflow {

// a plain comparison, not fmax (a library call unless NaNs are ruled out,
// and phi is never NaN)
KOKKOS_INLINE_FUNCTION Real larger(Real a, Real b) { return a > b ? a : b; }
KOKKOS_INLINE_FUNCTION Real smaller(Real a, Real b) { return a < b ? a : b; }

// index n of a line of `size` cells, clamped to it with Clamp
template <bool Clamp>
KOKKOS_INLINE_FUNCTION int line_index(int n, int size) {
  return Clamp ? (n < 0 ? 0 : (n < size ? n : size - 1)) : n;
}

// One implementation of both masks: the block's max (Below = false) or min
// (Below = true) by three separable passes, compared with threshold. The
// passes' ranges are clipped to the storage; with Below a block's reads are
// clamped to it too (a clamped read lands on a cell of the block already
// read, so the marks are exact): mark_near_below's cells reach the storage's
// edge, mark_near's lie `reach` inside it, where the clamp would only cost
// (it kept the max passes from vectorising: twice their time, measured).
// `labels` name the three passes.
struct PassLabels {
  const char *x, *y, *z;
};
template <bool Below, bool Raw = false>
inline void mark_block(const PassLabels& labels, const Field3& phi, Real threshold, int reach,
                       const Range3& cells, const Field3& pass_x, const Field3& pass_y, const Field3& out) {
  const int r = reach;
  const int sx = int(phi.extent(0)), sy = int(phi.extent(1)), sz = int(phi.extent(2));
  auto lo = [](int a) { return a > 0 ? a : 0; };
  auto hi = [](int a, int n) { return a < n ? a : n; };
  par_for(
      labels.x,
      Range3{cells.ib, cells.ie, lo(cells.jb - r), hi(cells.je + r, sy), lo(cells.kb - r),
             hi(cells.ke + r, sz)},
      KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = phi(i, j, k);
        for (int d = -r; d <= r; ++d) {
          const int n = i + d;
          const Real v = phi(line_index<Below>(n, sx), j, k);
          m = Below ? smaller(m, v) : larger(m, v);
        }
        pass_x(i, j, k) = m;
      });
  par_for(
      labels.y, Range3{cells.ib, cells.ie, cells.jb, cells.je, lo(cells.kb - r), hi(cells.ke + r, sz)},
      KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = pass_x(i, j, k);
        for (int d = -r; d <= r; ++d) {
          const int n = j + d;
          const Real v = pass_x(i, line_index<Below>(n, sy), k);
          m = Below ? smaller(m, v) : larger(m, v);
        }
        pass_y(i, j, k) = m;
      });
  par_for(
      labels.z, cells, KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = pass_y(i, j, k);
        for (int d = -r; d <= r; ++d) {
          const int n = k + d;
          const Real v = pass_y(i, j, line_index<Below>(n, sz));
          m = Below ? smaller(m, v) : larger(m, v);
        }
        if (Raw)
          out(i, j, k) = m;
        else
          out(i, j, k) = (Below ? m < threshold : m >= threshold) ? Real(1) : Real(0);
      });
}

// out(i, j, k) = 1 on the cells of `cells` whose block holds a phi >= threshold,
// else 0; pass_x and pass_y are scratch (out may be pass_x)
inline void mark_near(const Field3& phi, Real threshold, int reach, const Range3& cells, const Field3& pass_x,
                      const Field3& pass_y, const Field3& out) {
  mark_block<false>({"solid_near_x", "solid_near_y", "solid_near_z"}, phi, threshold, reach, cells, pass_x,
                    pass_y, out);
}

// out(i, j, k) = the largest phi in the cell's block: one field that serves as
// mark_near's mask for every threshold (out >= threshold), so the B
// extension's two bands share it (pass_x and pass_y scratch, out may be pass_x)
inline void block_max(const Field3& phi, int reach, const Range3& cells, const Field3& pass_x,
                      const Field3& pass_y, const Field3& out) {
  mark_block<false, true>({"solid_near_x", "solid_near_y", "solid_near_z"}, phi, 0, reach, cells, pass_x,
                          pass_y, out);
}

// out(i, j, k) = 1 on the cells of `cells` whose block holds a phi below
// threshold, else 0 (out may be pass_x); `cells` may reach the storage's edge
inline void mark_near_below(const Field3& phi, Real threshold, int reach, const Range3& cells,
                            const Field3& pass_x, const Field3& pass_y, const Field3& out) {
  mark_block<true>({"solid_near_below_x", "solid_near_below_y", "solid_near_below_z"}, phi, threshold, reach,
                   cells, pass_x, pass_y, out);
}

}  // namespace softflow
