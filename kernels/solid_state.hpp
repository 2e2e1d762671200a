// The solid phase on the grid: volume fraction phi and the six independent
// components of the left Cauchy-Green tensor B, all at cell centres.
// Component order: 0 xx, 1 xy, 2 xz, 3 yy, 4 yz, 5 zz.
#pragma once
#include <string>

#include "../src/grid.hpp"

namespace softflow {

// I's component m in B's six-component storage (0 xx, 1 xy, 2 xz, 3 yy, 4 yz, 5 zz)
KOKKOS_INLINE_FUNCTION Real identity_component(int m) { return (m == 0 || m == 3 || m == 5) ? 1 : 0; }

constexpr int n_solid_fields = 7;  // phi and B's six components

// B index of (a, b), a, b in {0, 1, 2}
KOKKOS_INLINE_FUNCTION int sym_index(int a, int b) {
  constexpr int idx[3][3] = {{0, 1, 2}, {1, 3, 4}, {2, 4, 5}};
  return idx[a][b];
}

// det of the symmetric matrix with these six components
KOKKOS_INLINE_FUNCTION Real det_sym(Real xx, Real xy, Real xz, Real yy, Real yz, Real zz) {
  return xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
}

struct SolidFields {
  Field3 q[n_solid_fields];  // q[0] = phi, q[1 + m] = B_m
  SolidFields() = default;
  SolidFields(const Grid& g, const std::string& label) {
    const char* names[n_solid_fields] = {"phi", "Bxx", "Bxy", "Bxz", "Byy", "Byz", "Bzz"};
    for (int m = 0; m < n_solid_fields; ++m) q[m] = Field3(label + "_" + names[m], g.sx(), g.sy(), g.sz());
  }
  const Field3& phi() const { return q[0]; }
  const Field3& B(int m) const { return q[1 + m]; }
};

// The seven fields as one struct of Views, for capture in kernels
struct SolidViews {
  Field3 phi, b0, b1, b2, b3, b4, b5;
  explicit SolidViews(const SolidFields& f)
      : phi(f.q[0]), b0(f.q[1]), b1(f.q[2]), b2(f.q[3]), b3(f.q[4]), b4(f.q[5]), b5(f.q[6]) {}
  KOKKOS_INLINE_FUNCTION const Field3& field(int m) const {
    switch (m) {
      case 0:
        return phi;
      case 1:
        return b0;
      case 2:
        return b1;
      case 3:
        return b2;
      case 4:
        return b3;
      case 5:
        return b4;
      default:
        return b5;
    }
  }
  KOKKOS_INLINE_FUNCTION Real B(int m, int i, int j, int k) const { return field(1 + m)(i, j, k); }
};

}  // namespace softflow
