// Lost solid back to its particle (particles.debris_return).
//
// Why: at 4 points per radius a Ca = 2 particle is a blade two to three cells
// across whose tips are a cell or two wide. MTHINC's one plane per cell cannot
// follow them, and the tips shed solid into the outer flow, which draws it
// along the flow into threads and wisps that no elastic force holds (the
// extension gives them B; results/README.md, rounds 39-40). A neo-Hookean
// particle cannot lose material, so that solid is a numerical error; left in
// place it grows with strain (0.2% of the volume a strain unit at Ca = 2)
// and carries up to a tenth of the particle's elastic shear stress.
//
// What: debris is every cell with phi > 0 and no phi >= debris_core_phi
// within two cells (block_max with reach 2, the extension's mask,
// kernels/near_mask.hpp). Its volume goes to the other cells in proportion to
// c (1 - c), as the clip's (kernels/solid_transport.hpp): the interface cells
// of the particles, never a full or an empty one. So phi stays in [0, 1] and
// the solid volume is conserved to round-off. A particle's own interface band
// loses only its far tail: MTHINC's tanh step (steepness 3.5) is below 3e-8
// beyond 2.5 cells of its 1/2 level (the dilute Ca = 0.2 run returned 3.5e-5
// of its volume in 20 strain units). The debris' B becomes I.
// Limits: the volume goes to every particle's interface, not the one it came
// from (one phi field: with colour fields the next stage's sum would undo
// it, so SolidPhase refuses the two together); a piece that breaks off with a
// core above 1/2 is a body, not debris, and stays.
#pragma once
#include "solid_state.hpp"
#include "solid_transport.hpp"

namespace softflow {

constexpr Real debris_core_phi = 0.5;  // a cell with this within two cells is a particle's

// Debris sums over `region` into s (this rank's): s[0] the debris' volume,
// s[1] the interface weight sum c (1 - c) of the cells that stay, s[2] the
// whole volume. near_max: the largest phi within two cells.
inline void debris_sums(const Field3& phi, const Field3& near_max, const Range3& region, Real s[3]) {
  s[0] = s[1] = s[2] = 0;
  par_reduce(
      "solid_debris_volume", region,
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        if (near_max(i, j, k) < debris_core_phi) a += phi(i, j, k);
      },
      Kokkos::Sum<Real>(s[0]));
  par_reduce(
      "solid_debris_weight", region,
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        const Real c = near_max(i, j, k) < debris_core_phi ? Real(0) : phi(i, j, k);
        a += c * (1 - c);
      },
      Kokkos::Sum<Real>(s[1]));
  par_reduce(
      "solid_debris_total", region, KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a += phi(i, j, k); },
      Kokkos::Sum<Real>(s[2]));
}

// The return with the global sums g (debris_sums' over all ranks): debris
// cells to phi = 0, B = I; the others c <- c + a c (1 - c), a = g[0] / g[1]
// (at most 1: beyond that the rest is not returned, and the volume drift
// diagnostic shows it)
inline void return_debris(const SolidFields& f, const Field3& near_max, const Range3& region,
                          const Real g[3]) {
  const Real a = redistribution_coefficient(g[0], g[1]);
  const SolidViews q(f);
  par_for(
      "solid_debris_return", region, KOKKOS_LAMBDA(int i, int j, int k) {
        if (near_max(i, j, k) < debris_core_phi) {
          q.phi(i, j, k) = 0;
          for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = identity_component(m);
        } else {
          q.phi(i, j, k) = redistributed_phi(q.phi(i, j, k), a, 0);
        }
      });
}

}  // namespace softflow
