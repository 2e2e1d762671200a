// Forces from the mixture stress of the one-continuum model, divided by rho:
//   viscous: div(2 mu(phi) D),  mu(phi) = (1 - phi) mu_f + phi mu_s
//   elastic: div(phi G (B - I))
// Normal stresses live at cell centres, shear stresses on the cell edges; the
// edge viscosity and the edge elastic stress are 4-cell arithmetic averages.
// G (B - I) is used rather than G B: the two differ by an isotropic part the
// pressure absorbs, and B - I vanishes in the undeformed solid, so a solid at
// rest carries no stress and every diagnostic uses G (B - I).
#pragma once
#include "flow_state.hpp"
#include "solid_state.hpp"

namespace softflow {

// phi as a material fraction: transported phi may over- or undershoot [0, 1] slightly
KOKKOS_INLINE_FUNCTION Real fraction(Real phi) { return Kokkos::fmin(Real(1), Kokkos::fmax(Real(0), phi)); }

struct MixtureStress {
  Real idx, idy, idz;
  Real nu_f, dnu;  // kinematic: mu / rho = nu_f + dnu phi
  Real g_rho;      // G / rho

  KOKKOS_INLINE_FUNCTION Real nu(const Field3& phi, int i, int j, int k) const {
    return nu_f + dnu * fraction(phi(i, j, k));
  }
  // nu on the edge between cells (i,j), (i+di,j+dj) ... spanning two directions
  KOKKOS_INLINE_FUNCTION Real nu_edge(const Field3& phi, int i, int j, int k, int di, int dj, int dk,
                                      int ei, int ej, int ek) const {
    return nu_f + dnu * 0.25 *
                      (fraction(phi(i, j, k)) + fraction(phi(i + di, j + dj, k + dk)) +
                       fraction(phi(i + ei, j + ej, k + ek)) +
                       fraction(phi(i + di + ei, j + dj + ej, k + dk + ek)));
  }

  // x-component at the u-face (i+1/2, j, k)
  KOKKOS_INLINE_FUNCTION Real viscous_u(const Field3& u, const Field3& v, const Field3& w,
                                        const Field3& phi, int i, int j, int k) const {
    const Real txp = 2 * nu(phi, i + 1, j, k) * (u(i + 1, j, k) - u(i, j, k)) * idx;
    const Real txm = 2 * nu(phi, i, j, k) * (u(i, j, k) - u(i - 1, j, k)) * idx;
    const Real typ = nu_edge(phi, i, j, k, 1, 0, 0, 0, 1, 0) *
                     ((u(i, j + 1, k) - u(i, j, k)) * idy + (v(i + 1, j, k) - v(i, j, k)) * idx);
    const Real tym = nu_edge(phi, i, j - 1, k, 1, 0, 0, 0, 1, 0) *
                     ((u(i, j, k) - u(i, j - 1, k)) * idy + (v(i + 1, j - 1, k) - v(i, j - 1, k)) * idx);
    const Real tzp = nu_edge(phi, i, j, k, 1, 0, 0, 0, 0, 1) *
                     ((u(i, j, k + 1) - u(i, j, k)) * idz + (w(i + 1, j, k) - w(i, j, k)) * idx);
    const Real tzm = nu_edge(phi, i, j, k - 1, 1, 0, 0, 0, 0, 1) *
                     ((u(i, j, k) - u(i, j, k - 1)) * idz + (w(i + 1, j, k - 1) - w(i, j, k - 1)) * idx);
    return (txp - txm) * idx + (typ - tym) * idy + (tzp - tzm) * idz;
  }

  // y-component at the v-face (i, j+1/2, k)
  KOKKOS_INLINE_FUNCTION Real viscous_v(const Field3& u, const Field3& v, const Field3& w,
                                        const Field3& phi, int i, int j, int k) const {
    const Real typ = 2 * nu(phi, i, j + 1, k) * (v(i, j + 1, k) - v(i, j, k)) * idy;
    const Real tym = 2 * nu(phi, i, j, k) * (v(i, j, k) - v(i, j - 1, k)) * idy;
    const Real txp = nu_edge(phi, i, j, k, 1, 0, 0, 0, 1, 0) *
                     ((u(i, j + 1, k) - u(i, j, k)) * idy + (v(i + 1, j, k) - v(i, j, k)) * idx);
    const Real txm = nu_edge(phi, i - 1, j, k, 1, 0, 0, 0, 1, 0) *
                     ((u(i - 1, j + 1, k) - u(i - 1, j, k)) * idy + (v(i, j, k) - v(i - 1, j, k)) * idx);
    const Real tzp = nu_edge(phi, i, j, k, 0, 1, 0, 0, 0, 1) *
                     ((v(i, j, k + 1) - v(i, j, k)) * idz + (w(i, j + 1, k) - w(i, j, k)) * idy);
    const Real tzm = nu_edge(phi, i, j, k - 1, 0, 1, 0, 0, 0, 1) *
                     ((v(i, j, k) - v(i, j, k - 1)) * idz + (w(i, j + 1, k - 1) - w(i, j, k - 1)) * idy);
    return (txp - txm) * idx + (typ - tym) * idy + (tzp - tzm) * idz;
  }

  // z-component at the w-face (i, j, k+1/2)
  KOKKOS_INLINE_FUNCTION Real viscous_w(const Field3& u, const Field3& v, const Field3& w,
                                        const Field3& phi, int i, int j, int k) const {
    const Real tzp = 2 * nu(phi, i, j, k + 1) * (w(i, j, k + 1) - w(i, j, k)) * idz;
    const Real tzm = 2 * nu(phi, i, j, k) * (w(i, j, k) - w(i, j, k - 1)) * idz;
    const Real txp = nu_edge(phi, i, j, k, 1, 0, 0, 0, 0, 1) *
                     ((u(i, j, k + 1) - u(i, j, k)) * idz + (w(i + 1, j, k) - w(i, j, k)) * idx);
    const Real txm = nu_edge(phi, i - 1, j, k, 1, 0, 0, 0, 0, 1) *
                     ((u(i - 1, j, k + 1) - u(i - 1, j, k)) * idz + (w(i, j, k) - w(i - 1, j, k)) * idx);
    const Real typ = nu_edge(phi, i, j, k, 0, 1, 0, 0, 0, 1) *
                     ((v(i, j, k + 1) - v(i, j, k)) * idz + (w(i, j + 1, k) - w(i, j, k)) * idy);
    const Real tym = nu_edge(phi, i, j - 1, k, 0, 1, 0, 0, 0, 1) *
                     ((v(i, j - 1, k + 1) - v(i, j - 1, k)) * idz + (w(i, j, k) - w(i, j - 1, k)) * idy);
    return (txp - txm) * idx + (typ - tym) * idy + (tzp - tzm) * idz;
  }

  // elastic stress tau_m / rho = (G / rho) phi (B_m - delta_m) at a cell centre
  KOKKOS_INLINE_FUNCTION Real tau(const SolidViews& s, int m, int i, int j, int k) const {
    const Real delta = (m == 0 || m == 3 || m == 5) ? 1 : 0;
    return g_rho * fraction(s.phi(i, j, k)) * (s.B(m, i, j, k) - delta);
  }
  // average of tau_m over the 4 cells around an edge: (i,j,k), +d, +e, +d+e
  KOKKOS_INLINE_FUNCTION Real tau_edge(const SolidViews& s, int m, int i, int j, int k, int di, int dj,
                                       int dk, int ei, int ej, int ek) const {
    return 0.25 * (tau(s, m, i, j, k) + tau(s, m, i + di, j + dj, k + dk) +
                   tau(s, m, i + ei, j + ej, k + ek) + tau(s, m, i + di + ei, j + dj + ej, k + dk + ek));
  }

  KOKKOS_INLINE_FUNCTION Real elastic_u(const SolidViews& s, int i, int j, int k) const {
    return (tau(s, 0, i + 1, j, k) - tau(s, 0, i, j, k)) * idx +
           (tau_edge(s, 1, i, j, k, 1, 0, 0, 0, 1, 0) - tau_edge(s, 1, i, j - 1, k, 1, 0, 0, 0, 1, 0)) * idy +
           (tau_edge(s, 2, i, j, k, 1, 0, 0, 0, 0, 1) - tau_edge(s, 2, i, j, k - 1, 1, 0, 0, 0, 0, 1)) * idz;
  }
  KOKKOS_INLINE_FUNCTION Real elastic_v(const SolidViews& s, int i, int j, int k) const {
    return (tau_edge(s, 1, i, j, k, 1, 0, 0, 0, 1, 0) - tau_edge(s, 1, i - 1, j, k, 1, 0, 0, 0, 1, 0)) * idx +
           (tau(s, 3, i, j + 1, k) - tau(s, 3, i, j, k)) * idy +
           (tau_edge(s, 4, i, j, k, 0, 1, 0, 0, 0, 1) - tau_edge(s, 4, i, j, k - 1, 0, 1, 0, 0, 0, 1)) * idz;
  }
  KOKKOS_INLINE_FUNCTION Real elastic_w(const SolidViews& s, int i, int j, int k) const {
    return (tau_edge(s, 2, i, j, k, 1, 0, 0, 0, 0, 1) - tau_edge(s, 2, i - 1, j, k, 1, 0, 0, 0, 0, 1)) * idx +
           (tau_edge(s, 4, i, j, k, 0, 1, 0, 0, 0, 1) - tau_edge(s, 4, i, j - 1, k, 0, 1, 0, 0, 0, 1)) * idy +
           (tau(s, 5, i, j, k + 1) - tau(s, 5, i, j, k)) * idz;
  }
};

}  // namespace softflow
