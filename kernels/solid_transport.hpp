// Right-hand sides of the solid fields:
//   d phi / dt = -div(u phi)
//   d B / dt   = -div(u B) + L B + B L^T      (upper-convected derivative zero)
// Advection in conservative flux form: each face flux is the MAC face
// velocity times the upwind value of the field at that face, so the
// solid volume sum(phi) changes only through round-off (the fluxes telescope).
// B's face values are WENO5 (Jiang-Shu); phi's are THINC (kernels/thinc.hpp,
// the default: keeps the interface one to two cells thick over long strains)
// or WENO5 (the reference study's scheme, particles.phi_scheme = "weno5").
// Both over- and undershoot phi at the interface slightly in 3-D;
// phi_bounded_redistribution() below clips them and gives the
// clipped volume back to the interface cells, so phi stays in [0, 1] and the
// solid volume stays conserved to round-off. Cells whose whole
// stencil is fluid (phi below the cut-off) get a zero right-hand side for B:
// B is reset to I there anyway. phi's own flux is computed on every face of
// the region: a face next to a fluid cell can carry a tiny flux, and
// skipping it would break the exact conservation of solid volume.
#pragma once
#include <algorithm>
#include <cmath>
#include <functional>

#include "flow_state.hpp"
#include "solid_b_fallback.hpp"
#include "solid_state.hpp"
#include "velocity_gradient.hpp"
#include "mthinc.hpp"
#include "near_mask.hpp"
#include "thinc.hpp"
#include "weno5.hpp"
#include "../src/x_runs.hpp"

namespace softflow {

constexpr Real phi_fluid_cut = 1e-6;  // below this a cell is fluid: B = I there

// With B extended from the solid side (kernels/solid_extension.hpp), B's
// transported value survives a stage only where phi ends it at or above 1/2:
// every other cell gets the extension's B, or I. So B's right-hand side is
// computed only in "live" cells, those with phi >= phi_b_live somewhere in
// their 3x3x3 block at the stage's start. A dead cell's centre is at least
// 1.5 cells from the 1/2 level of a tanh step of steepness 3.5 (a cell mean
// of 0.05 lies within half a cell of it), and the interface moves less than
// a cell per step (CFL 0.9): a dead cell cannot end a step solid.
// (With b_solid_phi below 1/2 B's own value survives from phi = b_solid_phi
// >= 0.2; a dead cell, below 0.05 across its block, does not reach that
// either in one step: tests/test_solid_region.cpp runs it with the mask and
// without.) With the
// extension after every stage (particles.b_extension_stages = "all")
// results are unchanged to the last bit (tests/test_solid_region.cpp); with
// it after a step's last stage only (the default), a dead cell keeps the
// last step's extended B through the step instead of two stages of the
// fluid's stretch. The dense step saves the B source and divergence of its
// dead cells (perf/README.md).
constexpr Real phi_b_live = 0.05;

KOKKOS_INLINE_FUNCTION Real weno_x(const Field3& q, Real vel, int i, int j,
                                   int k) {  // face i+1/2
  return weno5_face(vel, q(i - 2, j, k), q(i - 1, j, k), q(i, j, k), q(i + 1, j, k), q(i + 2, j, k),
                    q(i + 3, j, k));
}
KOKKOS_INLINE_FUNCTION Real weno_y(const Field3& q, Real vel, int i, int j,
                                   int k) {  // face j+1/2
  return weno5_face(vel, q(i, j - 2, k), q(i, j - 1, k), q(i, j, k), q(i, j + 1, k), q(i, j + 2, k),
                    q(i, j + 3, k));
}
KOKKOS_INLINE_FUNCTION Real weno_z(const Field3& q, Real vel, int i, int j,
                                   int k) {  // face k+1/2
  return weno5_face(vel, q(i, j, k - 2), q(i, j, k - 1), q(i, j, k), q(i, j, k + 1), q(i, j, k + 2),
                    q(i, j, k + 3));
}

// sdx = the stage's time step over dx: the face's Courant number is |vel| sdx
KOKKOS_INLINE_FUNCTION Real thinc_x(const Field3& q, Real vel, const Thinc& t, Real sdx, int i, int j,
                                    int k) {
  return thinc_face(vel, q(i - 1, j, k), q(i, j, k), q(i + 1, j, k), q(i + 2, j, k), t,
                    Kokkos::fabs(vel) * sdx);
}
KOKKOS_INLINE_FUNCTION Real thinc_y(const Field3& q, Real vel, const Thinc& t, Real sdy, int i, int j,
                                    int k) {
  return thinc_face(vel, q(i, j - 1, k), q(i, j, k), q(i, j + 1, k), q(i, j + 2, k), t,
                    Kokkos::fabs(vel) * sdy);
}
KOKKOS_INLINE_FUNCTION Real thinc_z(const Field3& q, Real vel, const Thinc& t, Real sdz, int i, int j,
                                    int k) {
  return thinc_face(vel, q(i, j, k - 1), q(i, j, k), q(i, j, k + 1), q(i, j, k + 2), t,
                    Kokkos::fabs(vel) * sdz);
}

// phi's face values: THINC with steepness beta (direction by direction, or
// MTHINC's plane with multi_d), or WENO5 (beta <= 0).
// stage_dt: the time this RK3 stage advances phi by ((gamma + zeta) dt, the
// stage's share of the step), which sets THINC's swept region at each face.
struct PhiScheme {
  Real thinc_beta = 0;
  bool multi_d = false;
  Real stage_dt = 0;
  // phi is the sum of colour fields transported on their own
  // (src/colour_fields.hpp): solid_transport_rhs leaves phi's right-hand side 0
  bool phi_from_colours = false;
  bool thinc() const { return thinc_beta > 0; }
};

// Youngs' gradient of phi at a cell: central differences averaged over the
// 3x3 neighbours across, weights 1-2-1 (smoother than one central
// difference, so the normal of a curved interface does not jitter cell to cell)
KOKKOS_INLINE_FUNCTION void youngs_gradient(const Field3& q, int i, int j, int k, Real g[3]) {
  const Real w[3] = {1, 2, 1};
  g[0] = g[1] = g[2] = 0;
  for (int a = -1; a <= 1; ++a)
    for (int b = -1; b <= 1; ++b) {
      const Real ww = w[a + 1] * w[b + 1];
      g[0] += ww * (q(i + 1, j + a, k + b) - q(i - 1, j + a, k + b));
      g[1] += ww * (q(i + a, j + 1, k + b) - q(i + a, j - 1, k + b));
      g[2] += ww * (q(i + a, j + b, k + 1) - q(i + a, j + b, k - 1));
    }
}

// the largest phi on the cell's WENO stencil (the cell and 3 neighbours each
// way); a plain comparison, not fmax (a library call unless NaNs are ruled
// out, and phi is never NaN)
KOKKOS_INLINE_FUNCTION Real stencil_max(const Field3& phi, int i, int j, int k) {
  Real m = phi(i, j, k);
  for (int d = 1; d <= 3; ++d) {
    m = larger(m, larger(phi(i - d, j, k), phi(i + d, j, k)));
    m = larger(m, larger(phi(i, j - d, k), phi(i, j + d, k)));
    m = larger(m, larger(phi(i, j, k - d), phi(i, j, k + d)));
  }
  return m;
}

// B's upper-convected source L B + B L^T in cell (i, j, k), its six components
KOKKOS_INLINE_FUNCTION void b_source(const Field3& u, const Field3& v, const Field3& w, const SolidViews& q,
                                     int i, int j, int k, Real idx, Real idy, Real idz, Real out[6]) {
  const Gradient3 L = velocity_gradient(u, v, w, i, j, k, idx, idy, idz);
  Real B[6];
  for (int m = 0; m < 6; ++m) B[m] = q.B(m, i, j, k);
  const int a_of[6] = {0, 0, 0, 1, 1, 2}, b_of[6] = {0, 1, 2, 1, 2, 2};
  for (int m = 0; m < 6; ++m) out[m] = upper_convected_source(L, B, a_of[m], b_of[m]);
}

// Face fluxes u q of one field: x(i, j, k) at face i+1/2, y at j+1/2, z at
// k+1/2; with MTHINC also each cell's plane (normal n) and the exps its face
// values share (E, e1, e2, eD: kernels/mthinc.hpp). Scratch of the
// transport, allocated once.
struct FaceFluxes {
  Field3 x, y, z;
  Field3 nx, ny, nz, E, e1, e2, eD;  // MTHINC only
  FaceFluxes() = default;
  explicit FaceFluxes(const Grid& g, bool planes = false)
      : x("flux_x", g.sx(), g.sy(), g.sz()),
        y("flux_y", g.sx(), g.sy(), g.sz()),
        z("flux_z", g.sx(), g.sy(), g.sz()) {
    if (!planes) return;
    nx = Field3("plane_nx", g.sx(), g.sy(), g.sz());
    ny = Field3("plane_ny", g.sx(), g.sy(), g.sz());
    nz = Field3("plane_nz", g.sx(), g.sy(), g.sz());
    E = Field3("plane_E", g.sx(), g.sy(), g.sz());
    e1 = Field3("plane_e1", g.sx(), g.sy(), g.sz());
    e2 = Field3("plane_e2", g.sx(), g.sy(), g.sz());
    eD = Field3("plane_eD", g.sx(), g.sy(), g.sz());
  }
};

// B's live cells (with B's extension): `mask` from mark_near with reach 1
// and phi_b_live over the active cells grown by one; `faces` and `cells`
// the storage of the runs the transport finds in it (src/x_runs.hpp).
// Empty: B everywhere.
struct LiveCells {
  Field3 mask;
  XRuns faces, cells;
  LiveCells() = default;
  explicit LiveCells(const Grid& g)
      : mask("solid_b_live", g.sx(), g.sy(), g.sz()),
        faces("solid_b_live_faces", g.sy(), g.sz()),
        cells("solid_b_live_cells", g.sy(), g.sz()) {}
  bool on() const { return mask.data() != nullptr; }
};

// MTHINC's face values: the upwind cell's plane swept over the stage; n = 0
// marks a cell without interface. The plane's offset d is not stored: the
// face values need only its exp, E.
KOKKOS_INLINE_FUNCTION Real mthinc_face(const FaceFluxes& f, const Field3& q, Real vel, Real beta, Real sd,
                                        int ax, int i, int j, int k) {
  const bool pos = vel >= 0;
  const int iu = pos ? i : i + (ax == 0), ju = pos ? j : j + (ax == 1), ku = pos ? k : k + (ax == 2);
  MthincPlane p{{f.nx(iu, ju, ku), f.ny(iu, ju, ku), f.nz(iu, ju, ku)}, -1};
  if (p.n[0] == 0 && p.n[1] == 0 && p.n[2] == 0) return q(iu, ju, ku);
  p.dom = dominant_axis(p.n);
  const MthincExps x{f.E(iu, ju, ku), f.e1(iu, ju, ku), f.e2(iu, ju, ku), f.eD(iu, ju, ku)};
  return mthinc_face_value(p, x, q(iu, ju, ku), beta, ax, pos, Kokkos::fabs(vel) * sd);
}

// WENO5 face fluxes u q of one field on every face of `faces`
inline void weno_face_fluxes(const FlowState& flow, const Field3& q, const FaceFluxes& flux,
                             const Range3& faces) {
  auto u = flow.u, v = flow.v, w = flow.w;
  auto fx = flux.x, fy = flux.y, fz = flux.z;
  par_for(
      "solid_transport_flux", faces, KOKKOS_LAMBDA(int i, int j, int k) {
        fx(i, j, k) = u(i, j, k) * weno_x(q, u(i, j, k), i, j, k);
        fy(i, j, k) = v(i, j, k) * weno_y(q, v(i, j, k), i, j, k);
        fz(i, j, k) = w(i, j, k) * weno_z(q, w(i, j, k), i, j, k);
      });
}

// -div(u q) of one volume fraction (phi, or one colour's share of it) into
// r on `active`: face values by the phi scheme (MTHINC, THINC or WENO5), each
// face flux once into the scratch, then the divergence
inline void phi_transport_rhs(const Grid& g, const FlowState& flow, const Field3& q, const Field3& r,
                              const FaceFluxes& flux, const Range3& active, const PhiScheme& scheme) {
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  auto u = flow.u, v = flow.v, w = flow.w;
  auto fx = flux.x, fy = flux.y, fz = flux.z;
  const Range3 faces{active.ib - 1, active.ie, active.jb - 1, active.je, active.kb - 1, active.ke};
  if (scheme.thinc() && scheme.multi_d) {
    const Real beta = scheme.thinc_beta, e_beta = std::exp(beta);
    const Real sdx = scheme.stage_dt * idx, sdy = scheme.stage_dt * idy, sdz = scheme.stage_dt * idz;
    const FaceFluxes fl = flux;
    // the planes of every cell upwind of a face: one more on the high side
    const Range3 cells{faces.ib, faces.ie + 1, faces.jb, faces.je + 1, faces.kb, faces.ke + 1};
    par_for(
        "solid_transport_mthinc_planes", cells, KOKKOS_LAMBDA(int i, int j, int k) {
          Real gr[3] = {0, 0, 0};
          const Real qc = q(i, j, k);
          if (mthinc_interface(qc)) youngs_gradient(q, i, j, k, gr);
          MthincExps x;
          const MthincPlane p = mthinc_fit(qc, gr, beta, e_beta, x);
          fl.nx(i, j, k) = p.dom < 0 ? 0 : p.n[0];
          fl.ny(i, j, k) = p.dom < 0 ? 0 : p.n[1];
          fl.nz(i, j, k) = p.dom < 0 ? 0 : p.n[2];
          if (p.dom < 0) return;
          fl.E(i, j, k) = x.E;
          fl.e1(i, j, k) = x.e1;
          fl.e2(i, j, k) = x.e2;
          fl.eD(i, j, k) = x.eD;
        });
    par_for(
        "solid_transport_flux_mthinc", faces, KOKKOS_LAMBDA(int i, int j, int k) {
          fx(i, j, k) = u(i, j, k) * mthinc_face(fl, q, u(i, j, k), beta, sdx, 0, i, j, k);
          fy(i, j, k) = v(i, j, k) * mthinc_face(fl, q, v(i, j, k), beta, sdy, 1, i, j, k);
          fz(i, j, k) = w(i, j, k) * mthinc_face(fl, q, w(i, j, k), beta, sdz, 2, i, j, k);
        });
  } else if (scheme.thinc()) {
    const Thinc t = make_thinc(scheme.thinc_beta);
    const Real sdx = scheme.stage_dt * idx, sdy = scheme.stage_dt * idy, sdz = scheme.stage_dt * idz;
    par_for(
        "solid_transport_flux_thinc", faces, KOKKOS_LAMBDA(int i, int j, int k) {
          fx(i, j, k) = u(i, j, k) * thinc_x(q, u(i, j, k), t, sdx, i, j, k);
          fy(i, j, k) = v(i, j, k) * thinc_y(q, v(i, j, k), t, sdy, i, j, k);
          fz(i, j, k) = w(i, j, k) * thinc_z(q, w(i, j, k), t, sdz, i, j, k);
        });
  } else {
    weno_face_fluxes(flow, q, flux, faces);
  }
  par_for(
      "solid_transport_divergence", active, KOKKOS_LAMBDA(int i, int j, int k) {
        r(i, j, k) = -((fx(i, j, k) - fx(i - 1, j, k)) * idx + (fy(i, j, k) - fy(i, j - 1, k)) * idy +
                       (fz(i, j, k) - fz(i, j, k - 1)) * idz);
      });
}

// The advection part of the right-hand sides, -div(u q) of the seven fields,
// then B's upper-convected source. Each face flux is reconstructed once and
// stored (a cell-wise loop would reconstruct every face twice, and WENO5 is
// the step's most expensive arithmetic); one field at a time, so the scratch
// is three arrays. No per-cell tests around the reconstruction (branches at
// the interface cost more than they save, measured): a face flux of a field
// that is zero on its six-cell stencil is exactly zero, so phi' = 0 exactly
// away from the solid and the solid volume is conserved to round-off.
// `active` (inside `region`) holds the cells within 3 of phi's support at this
// stage; the rest of `region` gets zero right-hand sides. With `live` (B's
// extension): B's right-hand side only in its live cells, B's fluxes only on
// their faces, each looped over as runs (src/x_runs.hpp).
inline void solid_transport_rhs(const Grid& g, const FlowState& flow, const SolidFields& f,
                                const SolidFields& rhs, const FaceFluxes& flux, const Range3& region,
                                const Range3& active, PhiScheme scheme = {}, const LiveCells& live = {}) {
  {
    const SolidViews r(rhs);
    const Range3 a = active;
    par_for(
        "solid_transport_clear", region, KOKKOS_LAMBDA(int i, int j, int k) {
          if (a.contains(i, j, k)) return;
          for (int m = 0; m < n_solid_fields; ++m) r.field(m)(i, j, k) = 0;
        });
  }
  if (active.empty()) return;
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  auto u = flow.u, v = flow.v, w = flow.w;
  auto fx = flux.x, fy = flux.y, fz = flux.z;
  // the faces of the active cells: one more on the low side of each direction
  const Range3 faces{active.ib - 1, active.ie, active.jb - 1, active.je, active.kb - 1, active.ke};
  const Field3 b_live = live.mask;
  const bool masked = live.on();
  XRuns live_faces = live.faces, live_cells = live.cells;
  if (masked) {
    // B's faces next to a live cell (a cell's three faces together, so the
    // reconstruction stays one straight-line body; per-face tests made each
    // face twice as slow, measured), and the live cells
    find_runs(
        "solid_b_live_faces", faces,
        KOKKOS_LAMBDA(int i, int j, int k) {
          return b_live(i, j, k) != 0 || b_live(i + 1, j, k) != 0 || b_live(i, j + 1, k) != 0 ||
                 b_live(i, j, k + 1) != 0;
        },
        live_faces);
    find_runs(
        "solid_b_live_cells", active, KOKKOS_LAMBDA(int i, int j, int k) { return b_live(i, j, k) != 0; },
        live_cells);
  }
  for (int m = 0; m < n_solid_fields; ++m) {
    const Field3 q = f.q[m], r = rhs.q[m];
    if (m == 0) {
      if (scheme.phi_from_colours)
        par_for(
            "solid_transport_phi_zero", active, KOKKOS_LAMBDA(int i, int j, int k) { r(i, j, k) = 0; });
      else
        phi_transport_rhs(g, flow, q, r, flux, active, scheme);
      continue;
    }
    if (masked) {
      // the live faces' runs (and, past a line's run limit, a few more). The
      // labels are the unmasked kernels', so old and new numerics compare
      // kernel by kernel.
      par_for_runs(
          "solid_transport_flux", live_faces, KOKKOS_LAMBDA(int i, int j, int k) {
            fx(i, j, k) = u(i, j, k) * weno_x(q, u(i, j, k), i, j, k);
            fy(i, j, k) = v(i, j, k) * weno_y(q, v(i, j, k), i, j, k);
            fz(i, j, k) = w(i, j, k) * weno_z(q, w(i, j, k), i, j, k);
          });
    } else {
      weno_face_fluxes(flow, q, flux, faces);
    }
    if (masked) {
      par_for(
          "solid_transport_divergence", active, KOKKOS_LAMBDA(int i, int j, int k) {
            const Real d = (fx(i, j, k) - fx(i - 1, j, k)) * idx + (fy(i, j, k) - fy(i, j - 1, k)) * idy +
                           (fz(i, j, k) - fz(i, j, k - 1)) * idz;
            r(i, j, k) = b_live(i, j, k) != 0
                             ? -d
                             : Real(0);  // a select, not a branch: dead faces hold old finite values
          });
    } else {
      par_for(
          "solid_transport_divergence", active, KOKKOS_LAMBDA(int i, int j, int k) {
            r(i, j, k) = -((fx(i, j, k) - fx(i - 1, j, k)) * idx + (fy(i, j, k) - fy(i, j - 1, k)) * idy +
                           (fz(i, j, k) - fz(i, j, k - 1)) * idz);
          });
    }
  }
  const SolidViews q(f), r(rhs);
  if (masked) {
    // the live cells' runs; the dead cells' right-hand sides are 0 already
    // (the divergence's select), and a dead cell inside a stretched run gets
    // 0 again by a select, which keeps the runs' loops vectorisable (so is
    // the fluid test below, the same as the unmasked kernel's)
    par_for_runs(
        "solid_transport_source", live_cells, KOKKOS_LAMBDA(int i, int j, int k) {
          Real src[6];
          b_source(u, v, w, q, i, j, k, idx, idy, idz, src);
          const bool on = b_live(i, j, k) != 0 && !(stencil_max(q.phi, i, j, k) < phi_fluid_cut);
          for (int m = 0; m < 6; ++m) {
            const Real s = r.field(1 + m)(i, j, k) + src[m];
            r.field(1 + m)(i, j, k) = on ? s : Real(0);
          }
        });
    return;
  }
  par_for(
      "solid_transport_source", active, KOKKOS_LAMBDA(int i, int j, int k) {
        // fluid on the whole stencil (B is I there): B has no right-hand side
        if (stencil_max(q.phi, i, j, k) < phi_fluid_cut) {
          for (int m = 1; m < n_solid_fields; ++m) r.field(m)(i, j, k) = 0;
          return;
        }
        Real src[6];
        b_source(u, v, w, q, i, j, k, idx, idy, idz, src);
        for (int m = 0; m < 6; ++m) r.field(1 + m)(i, j, k) += src[m];
      });
}

// q += gdt * now + zdt * before for the seven fields; then B is reset to I
// where phi < phi_fluid_cut: in pure fluid B has no meaning (its stress is
// multiplied by phi) and, left alone in sheared fluid, would grow without
// bound and leak into the interface through the WENO stencils. With
// check.on, a cell whose new B is not admissible keeps its stage-start B and
// is flagged for the first-order fallback (kernels/solid_b_fallback.hpp).
inline void solid_rk3_update(const SolidFields& f, const SolidFields& now, const SolidFields& before,
                             Real gdt, Real zdt, const Range3& region, const BCheck& check = {}) {
  const SolidViews q(f), a(now), b(before);
  const bool on = check.on;
  const Real det_tol = check.det_tol, phi_min = check.phi_min;
  const Field3 flag = check.flag;
  par_for(
      "solid_rk3_update", region, KOKKOS_LAMBDA(int i, int j, int k) {
        q.phi(i, j, k) += gdt * a.phi(i, j, k) + zdt * b.phi(i, j, k);
        Real bn[6];
        for (int m = 0; m < 6; ++m) bn[m] = q.B(m, i, j, k) + (gdt * a.B(m, i, j, k) + zdt * b.B(m, i, j, k));
        Real state = b_updated;
        if (q.phi(i, j, k) < phi_fluid_cut) {
          for (int m = 0; m < 6; ++m) bn[m] = identity_component(m);
          state = b_reset;
        } else if (on && q.phi(i, j, k) >= phi_min && !b_admissible(bn, det_tol)) {
          state = b_troubled;
        }
        if (on) flag(i, j, k) = state;
        if (state != b_troubled)
          for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = bn[m];
      });
}

// phi as kept: clamped to [0, 1], and 0 below phi_zero_cut. WENO5 leaves
// tails of tiny positive values that would otherwise creep ~3 cells per stage
// into the fluid and spread the solid region (kernels/solid_region.hpp) over
// the box; their volume goes back to the interface like the clipped excess.
// A colour field may keep a higher cut (particles.colour_cut): its work is
// on boxes about its support, which the tails set (src/colour_fields.hpp).
constexpr Real phi_zero_cut = 1e-10;
KOKKOS_INLINE_FUNCTION Real kept_phi(Real p, Real cut = phi_zero_cut) {
  return p < cut ? Real(0) : Kokkos::fmin(Real(1), p);
}

// Keeps phi in [0, 1] without losing solid volume. With c = kept_phi(phi),
// e = sum(phi - c) (the clipped volume, over all ranks) and W = sum c (1 - c),
// phi <- c + (e / W) c (1 - c). The added amount is largest mid-interface and
// vanishes where c is 0 or 1, and c + a c (1 - c) stays in [0, 1] for
// |a| <= 1, so the bounds hold exactly and the volume is conserved to
// round-off whenever |e| <= W (always seen in practice; otherwise the rest of
// e is dropped and the drift shows in the solid-volume diagnostic).
// (allreduce_sum is a std::function, not a template parameter: nvcc rejects a
// caller's local lambda type in the template arguments of a function that
// holds extended lambdas)
// Only the `n` disjoint boxes `region` are visited: phi is 0 outside them
// (kernels/solid_region.hpp; a colour's boxes, src/colour_boxes.hpp). In
// two halves, so that many fields (the colours) share one allreduce: this
// rank's {e, W} into sums[0..1], then, with the global sums, the update.
// Its point-wise parts, shared with the colours' batched loops
// (src/colour_fields.cpp): a cell's clipped volume p - c, its interface
// weight c (1 - c), the coefficient a = e / W clipped to [lowest, 1] (the
// colours' overlap bound takes [0, 1]), and the updated value.
KOKKOS_INLINE_FUNCTION Real clipped_excess(Real p, Real cut) { return p - kept_phi(p, cut); }
KOKKOS_INLINE_FUNCTION Real interface_weight(Real p, Real cut) {
  const Real c = kept_phi(p, cut);
  return c * (1 - c);
}
inline Real redistribution_coefficient(Real e, Real w, Real lowest = -1) {
  return w > 0 ? std::max(lowest, std::min(Real(1), e / w)) : Real(0);
}
KOKKOS_INLINE_FUNCTION Real redistributed_phi(Real p, Real a, Real cut) {
  const Real c = kept_phi(p, cut);
  return c + a * c * (1 - c);
}
inline void phi_redistribution_sums(const Field3& phi, const Range3* region, int n, Real* sums,
                                    Real cut = phi_zero_cut) {
  sums[0] = sums[1] = 0;
  for (int b = 0; b < n; ++b) {
    Real e = 0, w = 0;
    par_reduce(
        "solid_phi_excess", region[b],
        KOKKOS_LAMBDA(int i, int j, int k, Real& s) { s += clipped_excess(phi(i, j, k), cut); },
        Kokkos::Sum<Real>(e));
    par_reduce(
        "solid_phi_interface_weight", region[b],
        KOKKOS_LAMBDA(int i, int j, int k, Real& s) { s += interface_weight(phi(i, j, k), cut); },
        Kokkos::Sum<Real>(w));
    sums[0] += e;
    sums[1] += w;
  }
}
inline void phi_redistribute(const Field3& phi, const Real* global_sums, const Range3* region, int n,
                             Real cut = phi_zero_cut) {
  const Real a = redistribution_coefficient(global_sums[0], global_sums[1]);
  for (int b = 0; b < n; ++b)
    par_for(
        "solid_phi_redistribute", region[b],
        KOKKOS_LAMBDA(int i, int j, int k) { phi(i, j, k) = redistributed_phi(phi(i, j, k), a, cut); });
}
inline void phi_bounded_redistribution(const Field3& phi,
                                       const std::function<void(Real*, int)>& allreduce_sum,
                                       const Range3& region) {
  Real sums[2];
  phi_redistribution_sums(phi, &region, 1, sums);
  allreduce_sum(sums, 2);
  phi_redistribute(phi, sums, &region, 1);
}

// Wall ghosts of the solid fields from the First-th on (a template
// argument: the field loop is unrolled at compile time, and its switch over
// the fields with it): even reflection (no flux through the wall, and v = 0
// there makes the wall flux vanish anyway). Whole x-z plane.
template <int First = 0>
inline void apply_solid_walls(const Grid& g, const SolidFields& f) {
  const int ng = Grid::ng, ny = g.ny;
  const SolidViews q(f);
  par_for(
      "walls_solid", Range3{0, g.sx(), 0, ng, 0, g.sz()}, KOKKOS_LAMBDA(int i, int m, int k) {
        for (int c = First; c < n_solid_fields; ++c) {
          const Field3& a = q.field(c);
          a(i, ng - 1 - m, k) = a(i, ng + m, k);
          a(i, ng + ny + m, k) = a(i, ng + ny - 1 - m, k);
        }
      });
}

}  // namespace softflow
