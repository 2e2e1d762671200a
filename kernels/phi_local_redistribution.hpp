// Where phi's clipped volume goes: back into the interface next to where it
// was clipped (particles.phi_redistribution = "local"). The transport over-
// and undershoots phi by a little at the interface
// (kernels/solid_transport.hpp); clipping it to [0, 1] takes away a volume e
// per cell. The default, global redistribution (phi_bounded_redistribution)
// spreads the sum of e over every interface cell of the box, weighted by
// c (1 - c): solid moves from where the flow crosses the interface to
// everywhere else on it, and between particles. Here each cell's e goes to
// the interface cells of its own 3 x 3 x 3 neighbourhood:
//   W_j = sum over N(j) of w,  w = c (1 - c),  c = kept_phi(phi),
//   phi_i = c_i + w_i A_i,     A_i = sum over j in N(i) of e_j / W_j,
// which conserves volume exactly (sum_i w_i A_i = sum_j e_j) and keeps phi
// in [0, 1] where |A_i| <= 1. What does not fit (A_i clipped to [-1, 1], or
// a cell with no interface cell around it, W_j = 0) is returned by the
// caller to the global redistribution, which is then a tiny correction.
// Neighbours beyond the walls do not exist (j outside the interior).
// Measured (results/README.md, round 6): on the dilute Ca = 0.2 particle,
// which spreads along the vorticity axis over long runs, it changes nothing
// (the spread is not the redistribution's); kept as an option for dense
// suspensions, where the global one moves solid between particles.
#pragma once
#include "solid_transport.hpp"

namespace softflow {

// pass 1: phi <- c = kept_phi(phi), excess(i, j, k) = phi - c
inline void phi_clip_excess(const Field3& phi, const Field3& excess, const Range3& region) {
  par_for(
      "solid_phi_clip_excess", region, KOKKOS_LAMBDA(int i, int j, int k) {
        const Real p = phi(i, j, k), c = kept_phi(p);
        excess(i, j, k) = p - c;
        phi(i, j, k) = c;
      });
}

// w = c (1 - c) of a clipped phi
KOKKOS_INLINE_FUNCTION Real interface_weight(Real c) { return c * (1 - c); }

// pass 2 (phi's ghosts current): room(j) = W_j, the interface weight of j's
// neighbourhood, where j has an excess to place (0 elsewhere: not read)
inline void phi_neighbourhood_room(const Grid& g, const Field3& phi, const Field3& excess, const Field3& room,
                                   const Range3& region) {
  const int jlo = Grid::ng, jhi = Grid::ng + g.ny;
  par_for(
      "solid_phi_room", region, KOKKOS_LAMBDA(int i, int j, int k) {
        Real w = 0;
        if (excess(i, j, k) != 0)
          for (int b = -1; b <= 1; ++b) {
            if (j + b < jlo || j + b >= jhi) continue;
            for (int a = -1; a <= 1; ++a)
              for (int c = -1; c <= 1; ++c) w += interface_weight(phi(i + a, j + b, k + c));
          }
        room(i, j, k) = w;
      });
}

// pass 3 (excess and room ghosts current): phi_i = c_i + w_i A_i, A_i clipped
// to [-1, 1]; returns the volume (in cell units) left to place globally:
// what the clip cut off, and the excess of cells with no room around them
inline Real phi_place_excess(const Grid& g, const Field3& phi, const Field3& excess, const Field3& room,
                             const Range3& region) {
  const int jlo = Grid::ng, jhi = Grid::ng + g.ny;
  Real left = 0;
  par_reduce(
      "solid_phi_place", region,
      KOKKOS_LAMBDA(int i, int j, int k, Real& rest) {
        const Real e = excess(i, j, k);
        if (e != 0 && room(i, j, k) <= 0) rest += e;  // nowhere to go nearby
        const Real w = interface_weight(phi(i, j, k));
        if (w <= 0) return;
        Real A = 0;
        for (int b = -1; b <= 1; ++b) {
          if (j + b < jlo || j + b >= jhi) continue;
          for (int a = -1; a <= 1; ++a)
            for (int c = -1; c <= 1; ++c) {
              const Real W = room(i + a, j + b, k + c);
              if (W > 0) A += excess(i + a, j + b, k + c) / W;
            }
        }
        const Real Ac = Kokkos::fmax(Real(-1), Kokkos::fmin(Real(1), A));
        rest += w * (A - Ac);
        phi(i, j, k) += w * Ac;
      },
      Kokkos::Sum<Real>(left));
  return left;
}

// The rest, e (cell units, summed over the ranks by the caller), over every
// interface cell of the region: phi <- phi + (e / W) w, W the sum of w over
// all ranks (phi is in [0, 1] here: no clip, which would lose the tails)
inline void phi_spread_rest(const Field3& phi, Real e, const std::function<void(Real*, int)>& allreduce_sum,
                            const Range3& region) {
  Real W = 0;
  par_reduce(
      "solid_phi_rest_weight", region,
      KOKKOS_LAMBDA(int i, int j, int k, Real& w) { w += interface_weight(phi(i, j, k)); },
      Kokkos::Sum<Real>(W));
  allreduce_sum(&W, 1);
  const Real a = W > 0 ? Kokkos::fmax(Real(-1), Kokkos::fmin(Real(1), e / W)) : Real(0);
  par_for(
      "solid_phi_rest", region,
      KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) += a * interface_weight(phi(i, j, k)); });
}

}  // namespace softflow
