// B where the solid is a small share of a cell, and det B = 1 in the solid.
//
// Why: B obeys the upper-convected equation with the cell's velocity
// gradient. In an interface cell that is mostly fluid that gradient is the
// fluid's shear, not the particle's rotation, so B there is stretched without
// bound (det B reached 900-1700 in 0.001 < phi < 0.1 cells by strain 8), and
// tank-treading carries it back into the particle. The particle's B is
// smooth up to its surface (uniform, in the dilute exact solution), so:
//
// 1. Extension: in every cell with phi < phi_solid that has a cell with
//    phi >= phi_solid within two cells (a 5x5x5 block), B is replaced by the
//    phi-weighted, inverse-distance-weighted average of B over those cells.
//    B there then follows the solid side of the interface, as the reference
//    map technique's extrapolation does (Kamrin, Rycroft & Nave, JMPS 2012),
//    and the elastic stress phi G (B - I) of an interface cell is the phi
//    share of the solid stress beside it (mixture rule, METHOD.md). The pure
//    fluid cells next to the interface are included (their stress is zero):
//    the WENO5 stencils of the outer solid cells reach them, and a jump from
//    the solid's B to I there put det B errors of 2% per stage into those
//    solid cells (dense case, 4 points per radius). Cells without a solid
//    cell within two keep their B (I in the fluid; debris of a few 1e-3 of a
//    cell at most get I). Only cells with phi < phi_solid are written and
//    only cells with phi >= phi_solid read, so the kernel works in place and
//    in any order.
//    With particles.b_solid_phi above 1/2 an inner band pass comes first:
//    cells with 1/2 <= phi < b_solid_phi take the log-Euclidean mean B of
//    the core cells (phi >= b_solid_phi) within two cells, and keep their
//    own where there is none (a thin sheet). Their own equation sees the
//    band's mixture velocity gradient, which for a viscous particle (K > 1)
//    is the fluid's stronger shear: B there is over-stretched, and the
//    particle's mean B reads a more deformed particle than phi's shape
//    (results/README.md, "B from the core"). The log mean keeps det B: a
//    plain mean of the core's det-1 B put det B at 1.05-4.7 there.
//    With particles.b_solid_phi below 1/2 (the thin-particle setting) there
//    is no inner band, and the outer band's line moves down to it: B's own
//    equation in every cell with phi >= b_solid_phi. A blade two or three
//    cells across then has cells on its own B in every column, so its stress
//    feels its own stretch and it does not neck (results/README.md, rounds
//    39-40); SolidPhase passes the line as ExtensionBand's source_min.
// When: by default after each step's last RK3 stage only (particles.
//    b_extension_stages = "last"); "all" extends after every stage. In
//    between, the band's B follows its own equation for up to two stages, a
//    stretch of the order of the shear rate times dt, which the next
//    extension replaces; the extension and its masks and logs were a fifth
//    of the dense step at every stage (perf/README.md, round 29).
// 2. Unimodular projection (optional, after every stage): B <- B / det(B)^(1/3) in every cell
//    of the solid region (fluid cells far from the solid hold I: unchanged). An incompressible neo-Hookean
//    solid has det B = 1; the discrete upper-convected transport does not keep it, and the volumetric error
//    has no restoring force (the pressure absorbs isotropic stress), so it accumulates over long runs. The
//    kernel reports the range of det B in phi > 0.5 cells before the projection, and the elastic shear stress
//    the projection removes, so that both can be checked.
#pragma once
#include <stdexcept>

#include "mixture_stress.hpp"
#include "solid_state.hpp"
#include "sym_matrix_log.hpp"

namespace softflow {

constexpr Real phi_solid = 0.5;  // at or above: B evolves by its own equation (by default)

// Which cells the extension writes and which it reads: it writes the cells
// with target_min <= phi < source_min and reads those with phi >= source_min,
// so it works in place and in any order. A written cell with no source within
// two cells keeps its own B when keep_unreached, else gets I (when phi > 0).
// With logs (from log_core_b) the mean is log-Euclidean, exp(sum w log B /
// sum w): its det is the weighted geometric mean of the sources'
// (kernels/sym_matrix_log.hpp), where the plain mean of det-1 matrices of
// different orientations has det > 1 (1.2-4.7 in the inner band of the dense
// Ca = 0.2 and the Ca = 2 runs).
struct ExtensionBand {
  Real target_min = -1, source_min = phi_solid;  // by default every cell below source_min
  bool keep_unreached = false;
  SolidFields logs;  // empty: the plain mean
  bool log_mean() const { return logs.phi().data() != nullptr; }
};

// The sources' log B, each taken once per stage: a core cell is read by up to
// 124 band cells, and a matrix log per read made the inner band 40% of the
// dense step (perf/README.md). In `logs`, q[1 + m] = log B_m and q[0] = 1
// where it was taken: the cells of `cells` with phi >= source_min and `need`
// (mark_near_below with reach 2 and threshold source_min: a band cell within
// two cells); 0 elsewhere, and where B is not positive definite (a broken
// source: no band cell reads it, and the run's checks catch it).
inline void log_core_b(const SolidFields& f, const Range3& cells, Real source_min, const Field3& need,
                       const SolidFields& logs) {
  const SolidViews q(f), l(logs);
  par_for(
      "solid_b_core_log", cells, KOKKOS_LAMBDA(int i, int j, int k) {
        Real taken = 0;
        if (q.phi(i, j, k) >= source_min && need(i, j, k) > 0) {
          Real b[6], lg[6];
          for (int m = 0; m < 6; ++m) b[m] = q.field(1 + m)(i, j, k);
          if (sym_log_positive(b, lg)) {
            for (int m = 0; m < 6; ++m) l.field(1 + m)(i, j, k) = lg[m];
            taken = 1;
          }
        }
        l.phi(i, j, k) = taken;
      });
}

// The six arrays a band cell's mean reads, raw (below). At namespace scope:
// nvcc rejects a function's local type in a device lambda's captures.
struct ExtensionSources {
  const Real* b[6];
};

// B of the band's cells of `region` from the source cells within two cells;
// `near` from mark_near (kernels/near_mask.hpp) with reach 2 and threshold
// band.source_min, or block_max's with reach 2 (a cell is near where
// near >= band.source_min: one field for both bands); with band.logs,
// log_core_b's over `region` grown by two
inline void extend_b_from_solid(const SolidFields& f, const Range3& region, const Field3& near,
                                const ExtensionBand& band = {}) {
  const SolidViews q(f), l(band.log_mean() ? band.logs : f);
  const Real lo = band.target_min, hi = band.source_min;
  const bool keep = band.keep_unreached, log_mean = band.log_mean();
  // The block's 124 neighbours by one offset each into raw arrays (every
  // solid field has the grid's layout): the Views' own index arithmetic,
  // repeated for seven arrays per neighbour, took a fifth of the kernel
  // (dense scene, 1 thread: 48-61 -> 38-39 ms a step; results identical)
  const long sj = long(q.phi.stride(1)), sk = long(q.phi.stride(2));
  if (long(l.phi.stride(1)) != sj || long(l.phi.stride(2)) != sk)
    throw std::logic_error("extend_b_from_solid: the fields' layouts differ");
  const Real* const phi_at = q.phi.data();
  const Real* const mark_at = l.phi.data();  // log_mean: where the log was taken
  const ExtensionSources src{{l.b0.data(), l.b1.data(), l.b2.data(), l.b3.data(), l.b4.data(), l.b5.data()}};
  par_for(
      log_mean ? "solid_b_extension_core" : "solid_b_extension", region, KOKKOS_LAMBDA(int i, int j, int k) {
        const Real pc = q.phi(i, j, k);
        if (pc >= hi || pc < lo) return;
        Real acc[6] = {0, 0, 0, 0, 0, 0}, wsum = 0;
        if (near(i, j, k) >= hi) {
          const long centre = i + sj * j + sk * k;
          for (int c = -2; c <= 2; ++c)
            for (int b = -2; b <= 2; ++b)
              for (int a = -2; a <= 2; ++a) {
                const long o = centre + a + sj * b + sk * c;
                const Real pn = phi_at[o];
                if (pn < hi) continue;
                // log_mean: l holds the logs; a broken source has none
                if (log_mean && mark_at[o] == 0) continue;
                const Real wgt = pn / Real(a * a + b * b + c * c);
                for (int m = 0; m < 6; ++m) acc[m] += wgt * src.b[m][o];
                wsum += wgt;
              }
        }
        if (wsum > 0) {
          for (int m = 0; m < 6; ++m) acc[m] /= wsum;
          if (log_mean) {
            Real mean[6];
            sym_exp(acc, mean);
            for (int m = 0; m < 6; ++m) acc[m] = mean[m];
          }
          for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = acc[m];
        } else if (pc > 0 && !keep) {
          for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = identity_component(m);
        }
      });
}

// What the projection measured: det B before it over phi > 0.5 cells, and
// over those cells the sums of phi B_xy it removed and kept (the elastic
// shear stress over G, times the cell volume). Band cells (phi < 0.5) are
// projected too but not counted: their B is the extension's, rebuilt every
// stage, not a material memory the projection could erase.
struct UnimodularStats {
  Real det_min = 1, det_max = 1, removed_xy = 0, kept_xy = 0;
};

// The range of det B over the cells of `region` with phi > 0.5 (the solid);
// min > max when there are none
inline Kokkos::MinMaxScalar<Real> det_b_range(const SolidFields& f, const Range3& region) {
  const SolidViews q(f);
  Kokkos::MinMaxScalar<Real> mm;
  par_reduce(
      "solid_b_det_range", region,
      KOKKOS_LAMBDA(int i, int j, int k, Kokkos::MinMaxScalar<Real>& a) {
        if (q.phi(i, j, k) <= 0.5) return;
        const Real d =
            det_sym(q.b0(i, j, k), q.b1(i, j, k), q.b2(i, j, k), q.b3(i, j, k), q.b4(i, j, k), q.b5(i, j, k));
        a.min_val = d < a.min_val ? d : a.min_val;
        a.max_val = d > a.max_val ? d : a.max_val;
      },
      Kokkos::MinMax<Real>(mm));
  return mm;
}

// B <- B / det(B)^(1/3) over `region`; returns this rank's statistics
inline UnimodularStats project_b_unimodular(const SolidFields& f, const Range3& region) {
  const SolidViews q(f);
  UnimodularStats s;
  const Kokkos::MinMaxScalar<Real> mm = det_b_range(f, region);
  s.det_min = mm.min_val;
  s.det_max = mm.max_val;
  Real removed = 0;
  par_reduce(
      "solid_b_unimodular", region,
      KOKKOS_LAMBDA(int i, int j, int k, Real& acc) {
        const Real p = q.phi(i, j, k);
        const Real d =
            det_sym(q.b0(i, j, k), q.b1(i, j, k), q.b2(i, j, k), q.b3(i, j, k), q.b4(i, j, k), q.b5(i, j, k));
        // a non-positive det B is a broken state: left alone for the run's
        // checks to catch rather than hidden by the projection. det B = 1
        // exactly (B = I: the fluid, most of a dense box) needs no cube root,
        // the kernel's cost: the scale would be 1 exactly.
        if (!(d > 0) || d == 1) return;
        const Real sc = 1 / Kokkos::cbrt(d);
        if (p > 0.5) acc += fraction(p) * q.b1(i, j, k) * (1 - sc);
        for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) *= sc;
      },
      Kokkos::Sum<Real>(removed));
  s.removed_xy = removed;
  Real kept = 0;
  par_reduce(
      "solid_b_shear_sum", region,
      KOKKOS_LAMBDA(int i, int j, int k, Real& acc) {
        const Real p = q.phi(i, j, k);
        if (p > 0.5) acc += fraction(p) * q.b1(i, j, k);
      },
      Kokkos::Sum<Real>(kept));
  s.kept_xy = kept;
  return s;
}

}  // namespace softflow
