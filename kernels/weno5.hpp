// Fifth-order WENO reconstruction (Jiang & Shu, JCP 1996) of a cell-centred
// quantity at the face between cells 0 and 1, from the upwind side.
// Point-wise and backend-neutral, unit-tested on the host.
#pragma once
#include "../src/types.hpp"

namespace softflow {

// Value at the right face of cell c from cells c-2..c+2 (flow in +direction).
KOKKOS_INLINE_FUNCTION Real weno5(Real qm2, Real qm1, Real q0, Real qp1, Real qp2) {
  constexpr Real eps = 1e-6;  // Jiang & Shu's epsilon (data of order one)
  const Real b0 = Real(13) / 12 * (qm2 - 2 * qm1 + q0) * (qm2 - 2 * qm1 + q0) +
                  Real(0.25) * (qm2 - 4 * qm1 + 3 * q0) * (qm2 - 4 * qm1 + 3 * q0);
  const Real b1 =
      Real(13) / 12 * (qm1 - 2 * q0 + qp1) * (qm1 - 2 * q0 + qp1) + Real(0.25) * (qm1 - qp1) * (qm1 - qp1);
  const Real b2 = Real(13) / 12 * (q0 - 2 * qp1 + qp2) * (q0 - 2 * qp1 + qp2) +
                  Real(0.25) * (3 * q0 - 4 * qp1 + qp2) * (3 * q0 - 4 * qp1 + qp2);
  const Real a0 = Real(0.1) / ((eps + b0) * (eps + b0));
  const Real a1 = Real(0.6) / ((eps + b1) * (eps + b1));
  const Real a2 = Real(0.3) / ((eps + b2) * (eps + b2));
  const Real p0 = (2 * qm2 - 7 * qm1 + 11 * q0) / 6;
  const Real p1 = (-qm1 + 5 * q0 + 2 * qp1) / 6;
  const Real p2 = (2 * q0 + 5 * qp1 - qp2) / 6;
  return (a0 * p0 + a1 * p1 + a2 * p2) / (a0 + a1 + a2);
}

// Upwind WENO5 value at face c+1/2 given the six cells c-2..c+3 and the face
// velocity: from the left for vel >= 0, mirrored from the right otherwise.
// The stencil is chosen first and reconstructed once: no branch around the
// arithmetic, so x lines vectorise on CPUs and GPU warps do not diverge.
KOKKOS_INLINE_FUNCTION Real weno5_face(Real vel, Real qm2, Real qm1, Real q0, Real qp1, Real qp2, Real qp3) {
  const bool left = vel >= 0;
  return weno5(left ? qm2 : qp3, left ? qm1 : qp2, left ? q0 : qp1, left ? qp1 : q0, left ? qp2 : qm1);
}

}  // namespace softflow
