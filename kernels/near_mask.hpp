// Which cells have a phi at or above a threshold within `reach` cells (a
// (2 reach + 1)^3 block): the B extension's cells near the solid (reach 2,
// phi >= 1/2) and the transport's live cells for B (reach 1, phi >= 0.05).
// Three separable max passes instead of the block's (2 reach + 1)^3 reads,
// each a plain comparison the compiler vectorises. And the reverse, which
// cells have a phi below a threshold within reach (min passes): the core
// cells whose B the inner band reads (kernels/solid_extension.hpp).
#pragma once
#include "../src/types.hpp"

namespace softflow {

// a plain comparison, not fmax (a library call unless NaNs are ruled out,
// and phi is never NaN)
KOKKOS_INLINE_FUNCTION Real larger(Real a, Real b) { return a > b ? a : b; }
KOKKOS_INLINE_FUNCTION Real smaller(Real a, Real b) { return a < b ? a : b; }

// out(i, j, k) = 1 on the cells of `cells` whose block holds a phi >= threshold,
// else 0; pass_x and pass_y are scratch (out may be pass_x)
inline void mark_near(const Field3& phi, Real threshold, int reach, const Range3& cells, const Field3& pass_x,
                      const Field3& pass_y, const Field3& out) {
  const int r = reach;
  par_for(
      "solid_near_x", Range3{cells.ib, cells.ie, cells.jb - r, cells.je + r, cells.kb - r, cells.ke + r},
      KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = phi(i - r, j, k);
        for (int d = 1 - r; d <= r; ++d) m = larger(m, phi(i + d, j, k));
        pass_x(i, j, k) = m;
      });
  par_for(
      "solid_near_y", Range3{cells.ib, cells.ie, cells.jb, cells.je, cells.kb - r, cells.ke + r},
      KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = pass_x(i, j - r, k);
        for (int d = 1 - r; d <= r; ++d) m = larger(m, pass_x(i, j + d, k));
        pass_y(i, j, k) = m;
      });
  par_for(
      "solid_near_z", cells, KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = pass_y(i, j, k - r);
        for (int d = 1 - r; d <= r; ++d) m = larger(m, pass_y(i, j, k + d));
        out(i, j, k) = m >= threshold ? Real(1) : Real(0);
      });
}

// out(i, j, k) = 1 on the cells of `cells` whose block holds a phi below
// threshold, else 0; pass_x and pass_y are scratch (out may be pass_x).
// `cells` may reach the storage's edge: a block's reads are clamped to the
// storage (a clamped read lands on a cell of the block already read, so the
// marks are exact).
inline void mark_near_below(const Field3& phi, Real threshold, int reach, const Range3& cells,
                            const Field3& pass_x, const Field3& pass_y, const Field3& out) {
  const int r = reach;
  const int sx = int(phi.extent(0)), sy = int(phi.extent(1)), sz = int(phi.extent(2));
  auto lo = [](int a) { return a > 0 ? a : 0; };
  auto hi = [](int a, int n) { return a < n ? a : n; };
  par_for(
      "solid_near_below_x",
      Range3{cells.ib, cells.ie, lo(cells.jb - r), hi(cells.je + r, sy), lo(cells.kb - r),
             hi(cells.ke + r, sz)},
      KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = phi(i, j, k);
        for (int d = -r; d <= r; ++d) {
          const int n = i + d;
          m = smaller(m, phi(n < 0 ? 0 : (n < sx ? n : sx - 1), j, k));
        }
        pass_x(i, j, k) = m;
      });
  par_for(
      "solid_near_below_y",
      Range3{cells.ib, cells.ie, cells.jb, cells.je, lo(cells.kb - r), hi(cells.ke + r, sz)},
      KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = pass_x(i, j, k);
        for (int d = -r; d <= r; ++d) {
          const int n = j + d;
          m = smaller(m, pass_x(i, n < 0 ? 0 : (n < sy ? n : sy - 1), k));
        }
        pass_y(i, j, k) = m;
      });
  par_for(
      "solid_near_below_z", cells, KOKKOS_LAMBDA(int i, int j, int k) {
        Real m = pass_y(i, j, k);
        for (int d = -r; d <= r; ++d) {
          const int n = k + d;
          m = smaller(m, pass_y(i, j, n < 0 ? 0 : (n < sz ? n : sz - 1)));
        }
        out(i, j, k) = m < threshold ? Real(1) : Real(0);
      });
}

}  // namespace softflow
