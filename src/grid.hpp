// Geometry of the staggered (MAC) grid, as one rank sees it.
//
// Cells are uniform. Pressure (and later phi, B) live at cell centres; u at
// x-faces, v at y-faces, w at z-faces. Storage index i holds the cell whose
// centre is at x = (x0 + i - g + 1/2) dx, and u(i) the face at its +x side,
// x = (x0 + i - g + 1) dx; likewise v(j) sits at y = -h + (j - g + 1) dy, so
// v(g - 1) is the bottom wall and v(g + ny - 1) the top wall.
#pragma once
#include "types.hpp"

namespace softflow {

struct Grid {
  static constexpr int ng = 3;  // ghost width (>= 3 for WENO5)
  int nx = 0, ny = 0, nz = 0;   // global cells
  int nxl = 0, nzl = 0;         // cells on this rank (y is never split in physical space)
  int x0 = 0, z0 = 0;           // global index of the first local cell
  Real lx = 0, ly = 0, lz = 0;
  Real dx = 0, dy = 0, dz = 0;

  Real h() const { return ly / 2; }
  // storage extents, ghosts included
  int sx() const { return nxl + 2 * ng; }
  int sy() const { return ny + 2 * ng; }
  int sz() const { return nzl + 2 * ng; }
  // interior cells
  Range3 interior() const { return {ng, ng + nxl, ng, ng + ny, ng, ng + nzl}; }
  // the v unknowns: every y-face but the two walls
  Range3 v_interior() const { return {ng, ng + nxl, ng, ng + ny - 1, ng, ng + nzl}; }
  Range3 all() const { return {0, sx(), 0, sy(), 0, sz()}; }
  long cells_global() const { return long(nx) * ny * nz; }

  // coordinates from storage indices
  KOKKOS_INLINE_FUNCTION Real xc(int i) const { return (x0 + i - ng + Real(0.5)) * dx; }
  KOKKOS_INLINE_FUNCTION Real xf(int i) const { return (x0 + i - ng + 1) * dx; }
  KOKKOS_INLINE_FUNCTION Real yc(int j) const { return -ly / 2 + (j - ng + Real(0.5)) * dy; }
  KOKKOS_INLINE_FUNCTION Real yf(int j) const { return -ly / 2 + (j - ng + 1) * dy; }
  KOKKOS_INLINE_FUNCTION Real zc(int k) const { return (z0 + k - ng + Real(0.5)) * dz; }
  KOKKOS_INLINE_FUNCTION Real zf(int k) const { return (z0 + k - ng + 1) * dz; }
};

}  // namespace softflow
