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

// phi as a material fraction: transported phi may over- or undershoot [0, 1]
// slightly (comparisons, not fmin/fmax: those are library calls on the host
// unless NaNs are ruled out, and this clamp runs 13 times per cell for nu(phi))
KOKKOS_INLINE_FUNCTION Real fraction(Real phi) { return phi < 0 ? Real(0) : (phi > 1 ? Real(1) : phi); }

struct MixtureStress {
  Real idx, idy, idz;
  Real nu_f, dnu;  // kinematic: mu / rho = nu_f + dnu phi
  Real g_rho;      // G / rho

  // x-component at the u-face (i+1/2, j, k); n gives nu at cell centres and
  // on the xy, xz, yz edges (NuFromPhi, or StoredNu below)
  template <class Nu>
  KOKKOS_INLINE_FUNCTION Real viscous_u(const Field3& u, const Field3& v, const Field3& w, const Nu& n, int i,
                                        int j, int k) const {
    const Real txp = 2 * n.centre(i + 1, j, k) * (u(i + 1, j, k) - u(i, j, k)) * idx;
    const Real txm = 2 * n.centre(i, j, k) * (u(i, j, k) - u(i - 1, j, k)) * idx;
    const Real typ =
        n.xy(i, j, k) * ((u(i, j + 1, k) - u(i, j, k)) * idy + (v(i + 1, j, k) - v(i, j, k)) * idx);
    const Real tym = n.xy(i, j - 1, k) *
                     ((u(i, j, k) - u(i, j - 1, k)) * idy + (v(i + 1, j - 1, k) - v(i, j - 1, k)) * idx);
    const Real tzp =
        n.xz(i, j, k) * ((u(i, j, k + 1) - u(i, j, k)) * idz + (w(i + 1, j, k) - w(i, j, k)) * idx);
    const Real tzm = n.xz(i, j, k - 1) *
                     ((u(i, j, k) - u(i, j, k - 1)) * idz + (w(i + 1, j, k - 1) - w(i, j, k - 1)) * idx);
    return (txp - txm) * idx + (typ - tym) * idy + (tzp - tzm) * idz;
  }

  // y-component at the v-face (i, j+1/2, k)
  template <class Nu>
  KOKKOS_INLINE_FUNCTION Real viscous_v(const Field3& u, const Field3& v, const Field3& w, const Nu& n, int i,
                                        int j, int k) const {
    const Real typ = 2 * n.centre(i, j + 1, k) * (v(i, j + 1, k) - v(i, j, k)) * idy;
    const Real tym = 2 * n.centre(i, j, k) * (v(i, j, k) - v(i, j - 1, k)) * idy;
    const Real txp =
        n.xy(i, j, k) * ((u(i, j + 1, k) - u(i, j, k)) * idy + (v(i + 1, j, k) - v(i, j, k)) * idx);
    const Real txm = n.xy(i - 1, j, k) *
                     ((u(i - 1, j + 1, k) - u(i - 1, j, k)) * idy + (v(i, j, k) - v(i - 1, j, k)) * idx);
    const Real tzp =
        n.yz(i, j, k) * ((v(i, j, k + 1) - v(i, j, k)) * idz + (w(i, j + 1, k) - w(i, j, k)) * idy);
    const Real tzm = n.yz(i, j, k - 1) *
                     ((v(i, j, k) - v(i, j, k - 1)) * idz + (w(i, j + 1, k - 1) - w(i, j, k - 1)) * idy);
    return (txp - txm) * idx + (typ - tym) * idy + (tzp - tzm) * idz;
  }

  // z-component at the w-face (i, j, k+1/2)
  template <class Nu>
  KOKKOS_INLINE_FUNCTION Real viscous_w(const Field3& u, const Field3& v, const Field3& w, const Nu& n, int i,
                                        int j, int k) const {
    const Real tzp = 2 * n.centre(i, j, k + 1) * (w(i, j, k + 1) - w(i, j, k)) * idz;
    const Real tzm = 2 * n.centre(i, j, k) * (w(i, j, k) - w(i, j, k - 1)) * idz;
    const Real txp =
        n.xz(i, j, k) * ((u(i, j, k + 1) - u(i, j, k)) * idz + (w(i + 1, j, k) - w(i, j, k)) * idx);
    const Real txm = n.xz(i - 1, j, k) *
                     ((u(i - 1, j, k + 1) - u(i - 1, j, k)) * idz + (w(i, j, k) - w(i - 1, j, k)) * idx);
    const Real typ =
        n.yz(i, j, k) * ((v(i, j, k + 1) - v(i, j, k)) * idz + (w(i, j + 1, k) - w(i, j, k)) * idy);
    const Real tym = n.yz(i, j - 1, k) *
                     ((v(i, j - 1, k + 1) - v(i, j - 1, k)) * idz + (w(i, j, k) - w(i, j - 1, k)) * idy);
    return (txp - txm) * idx + (typ - tym) * idy + (tzp - tzm) * idz;
  }

  // elastic stress tau_m / rho = (G / rho) phi (B_m - delta_m) at a cell centre
  KOKKOS_INLINE_FUNCTION Real tau(const SolidViews& s, int m, int i, int j, int k) const {
    const Real delta = identity_component(m);
    return g_rho * fraction(s.phi(i, j, k)) * (s.B(m, i, j, k) - delta);
  }
  // average of tau_m over the 4 cells around an edge: (i,j,k), +d, +e, +d+e;
  // t(m, i, j, k) gives tau_m at a cell centre (TauFromB or StoredTau below)
  template <class Tau>
  KOKKOS_INLINE_FUNCTION Real tau_edge(const Tau& t, int m, int i, int j, int k, int di, int dj, int dk,
                                       int ei, int ej, int ek) const {
    return 0.25 * (t(m, i, j, k) + t(m, i + di, j + dj, k + dk) + t(m, i + ei, j + ej, k + ek) +
                   t(m, i + di + ei, j + dj + ej, k + dk + ek));
  }

  template <class Tau>
  KOKKOS_INLINE_FUNCTION Real elastic_u(const Tau& t, int i, int j, int k) const {
    return (t(0, i + 1, j, k) - t(0, i, j, k)) * idx +
           (tau_edge(t, 1, i, j, k, 1, 0, 0, 0, 1, 0) - tau_edge(t, 1, i, j - 1, k, 1, 0, 0, 0, 1, 0)) * idy +
           (tau_edge(t, 2, i, j, k, 1, 0, 0, 0, 0, 1) - tau_edge(t, 2, i, j, k - 1, 1, 0, 0, 0, 0, 1)) * idz;
  }
  template <class Tau>
  KOKKOS_INLINE_FUNCTION Real elastic_v(const Tau& t, int i, int j, int k) const {
    return (tau_edge(t, 1, i, j, k, 1, 0, 0, 0, 1, 0) - tau_edge(t, 1, i - 1, j, k, 1, 0, 0, 0, 1, 0)) * idx +
           (t(3, i, j + 1, k) - t(3, i, j, k)) * idy +
           (tau_edge(t, 4, i, j, k, 0, 1, 0, 0, 0, 1) - tau_edge(t, 4, i, j, k - 1, 0, 1, 0, 0, 0, 1)) * idz;
  }
  template <class Tau>
  KOKKOS_INLINE_FUNCTION Real elastic_w(const Tau& t, int i, int j, int k) const {
    return (tau_edge(t, 2, i, j, k, 1, 0, 0, 0, 0, 1) - tau_edge(t, 2, i - 1, j, k, 1, 0, 0, 0, 0, 1)) * idx +
           (tau_edge(t, 4, i, j, k, 0, 1, 0, 0, 0, 1) - tau_edge(t, 4, i, j - 1, k, 0, 1, 0, 0, 0, 1)) * idy +
           (t(5, i, j, k + 1) - t(5, i, j, k)) * idz;
  }
};

// The mixture viscosity nu(phi) at cell centres and as 4-cell averages on the
// edges, evaluated from phi where it is needed
struct NuFromPhi {
  Real nu_f, dnu;
  Field3 phi;
  KOKKOS_INLINE_FUNCTION Real centre(int i, int j, int k) const {
    return nu_f + dnu * fraction(phi(i, j, k));
  }
  KOKKOS_INLINE_FUNCTION Real edge(int i, int j, int k, int di, int dj, int dk, int ei, int ej,
                                   int ek) const {
    return nu_f +
           dnu * 0.25 *
               (fraction(phi(i, j, k)) + fraction(phi(i + di, j + dj, k + dk)) +
                fraction(phi(i + ei, j + ej, k + ek)) + fraction(phi(i + di + ei, j + dj + ej, k + dk + ek)));
  }
  KOKKOS_INLINE_FUNCTION Real xy(int i, int j, int k) const { return edge(i, j, k, 1, 0, 0, 0, 1, 0); }
  KOKKOS_INLINE_FUNCTION Real xz(int i, int j, int k) const { return edge(i, j, k, 1, 0, 0, 0, 0, 1); }
  KOKKOS_INLINE_FUNCTION Real yz(int i, int j, int k) const { return edge(i, j, k, 0, 1, 0, 0, 0, 1); }
};

// ... and stored once per stage (the same arithmetic, so the same bits): the
// viscous kernels then read 4 arrays instead of clamping phi 18 times per face
struct StoredNu {
  Field3 c, exy, exz, eyz;
  KOKKOS_INLINE_FUNCTION Real centre(int i, int j, int k) const { return c(i, j, k); }
  KOKKOS_INLINE_FUNCTION Real xy(int i, int j, int k) const { return exy(i, j, k); }
  KOKKOS_INLINE_FUNCTION Real xz(int i, int j, int k) const { return exz(i, j, k); }
  KOKKOS_INLINE_FUNCTION Real yz(int i, int j, int k) const { return eyz(i, j, k); }
};

// tau_m evaluated from phi and B where it is needed
struct TauFromB {
  MixtureStress st;
  SolidViews q;
  KOKKOS_INLINE_FUNCTION Real operator()(int m, int i, int j, int k) const { return st.tau(q, m, i, j, k); }
};

// tau_m stored at cell centres once per stage: the force kernel then reads six
// arrays instead of evaluating phi's clamp and B - I at the 18 stencil points
// of each component (the same arithmetic, so the same bits)
struct StoredTau {
  Field3 t0, t1, t2, t3, t4, t5;
  KOKKOS_INLINE_FUNCTION Real operator()(int m, int i, int j, int k) const {
    switch (m) {
      case 0:
        return t0(i, j, k);
      case 1:
        return t1(i, j, k);
      case 2:
        return t2(i, j, k);
      case 3:
        return t3(i, j, k);
      case 4:
        return t4(i, j, k);
      default:
        return t5(i, j, k);
    }
  }
};

}  // namespace softflow
