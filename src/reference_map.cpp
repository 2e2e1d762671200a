#include "reference_map.hpp"

#include "../kernels/near_mask.hpp"
#include "../kernels/projection.hpp"
#include "../kernels/wall_bc.hpp"
#include "../kernels/reference_map.hpp"
#include "../kernels/solid_region.hpp"

namespace softflow {

namespace {
constexpr int fit_reach = 3;  // a band fit reads the valid cells within 3
// the band's layers beyond the cells mapping inside: 4, so that the WENO5
// stencils of the first layer's faces (3 cells upwind) read band values, not
// the far value; the soft edge keeps part of the first layer's advected value
constexpr int band_layers = 4;
constexpr int solid_reach =
    2;  // cells that can hold solid: within 2 (their central differences stay in the band)
// a step's work box around the cells mapping inside at its start: the inside
// set grows by at most one cell a refit (refmap_inside_kept; one refit a
// stage and one a correction pass), the band reaches band_layers beyond it,
// and the cells valid at the step's start must be reset to the far value if
// they leave the band; one cell to spare
int work_margin(int correction_passes) { return 3 + correction_passes + band_layers + 1; }
constexpr Real far_offset = 10;   // xi beyond the band: c + 10 r in every component, far outside the sphere
constexpr int share_samples = 4;  // sub-cells per direction for a cell's share of the sphere
// the soft edge's width (soft_edge_weight), in cells: a leaving cell keeps
// part of its own value until it maps a cell beyond the sphere (round 37:
// at 4 ppr, Ca = 0.2, det B's range over strain 0-7 went from [0.939, 1.049]
// to [0.979, 1.029] with it; two cells gave the same at Ca = 2)
constexpr Real soft_edge_cells = 1;
// the band fits' ridge weight toward the particle's mean gradient, per unit
// of the fit's total weight: small beside a fit whose points span 3-D (the
// gradient block's entries are of order the total weight), decisive where
// they do not
constexpr Real ridge = 0.05;

// the gradient of one field at a cell centre by central differences
struct CentralGradient {
  Field3 q;
  Real hx, hy, hz;  // 1 / (2 dx) ...
  CentralGradient(const Field3& f, const Grid& g)
      : q(f), hx(1 / (2 * g.dx)), hy(1 / (2 * g.dy)), hz(1 / (2 * g.dz)) {}
  KOKKOS_INLINE_FUNCTION void operator()(int i, int j, int k, Real d[3]) const {
    d[0] = (q(i + 1, j, k) - q(i - 1, j, k)) * hx;
    d[1] = (q(i, j + 1, k) - q(i, j - 1, k)) * hy;
    d[2] = (q(i, j, k + 1) - q(i, j, k - 1)) * hz;
  }
};

// grad xi at a cell centre, J[a][b] = d xi_a / d x_b
struct MapGradient {
  CentralGradient x0, x1, x2;
  MapGradient(const Field3* xi, const Grid& g) : x0(xi[0], g), x1(xi[1], g), x2(xi[2], g) {}
  KOKKOS_INLINE_FUNCTION void operator()(int i, int j, int k, Real J[3][3]) const {
    x0(i, j, k, J[0]);
    x1(i, j, k, J[1]);
    x2(i, j, k, J[2]);
  }
};

// grad xi of a cell whose centre maps outside: the gradient of the affine
// least-squares fit through the cells within 3 that map inside (central
// differences there would mix the band's cells, each continued by its own
// fit); false where those cells do not span 3-D
KOKKOS_INLINE_FUNCTION bool fitted_gradient(const Field3& inside, const Field3& x0, const Field3& x1,
                                            const Field3& x2, const Real h[3], const GradientPrior& p, int i,
                                            int j, int k, Real J[3][3]) {
  AffineFit fit;
  Real wsum = 0;
  constexpr int R = fit_reach;
  for (int c = -R; c <= R; ++c)
    for (int b = -R; b <= R; ++b)
      for (int a = -R; a <= R; ++a) {
        if (inside(i + a, j + b, k + c) == 0) continue;
        const Real o[3] = {Real(a), Real(b), Real(c)};
        const Real v[3] = {x0(i + a, j + b, k + c), x1(i + a, j + b, k + c), x2(i + a, j + b, k + c)};
        const Real w = Real(1) / Real(a * a + b * b + c * c);
        fit.add(o, v, w);
        wsum += w;
      }
  if (wsum == 0) return false;
  fit.prior(p.G, ridge * wsum);
  Real value[3], G[3][3];
  if (!fit.solve(value, G)) return false;
  for (int m = 0; m < 3; ++m)
    for (int b = 0; b < 3; ++b) J[m][b] = G[m][b] / h[b];
  return true;
}

// 1 where a cell's centre maps inside the reference sphere, else 0, on every
// cell of the storage (ghosts included: the masks read them)
void mark_inside(const Field3* xi, const Real* c, Real r, const Field3& out) {
  const Field3 x0 = xi[0], x1 = xi[1], x2 = xi[2];
  const Real c0 = c[0], c1 = c[1], c2 = c[2], r2 = r * r;
  const Range3 all{0, int(out.extent(0)), 0, int(out.extent(1)), 0, int(out.extent(2))};
  par_for(
      "refmap_inside", all, KOKKOS_LAMBDA(int i, int j, int k) {
        const Real a = x0(i, j, k) - c0, b = x1(i, j, k) - c1, e = x2(i, j, k) - c2;
        out(i, j, k) = a * a + b * b + e * e < r2 ? Real(1) : Real(0);
      });
}
}  // namespace

ReferenceMap::ReferenceMap(const Grid& g, const Real c[3], Real r, int correction_passes)
    : correction_passes_(correction_passes), r_(r) {
  const char* names[3] = {"xi_x", "xi_y", "xi_z"};
  for (int m = 0; m < 3; ++m) {
    c_[m] = c[m];
    xi_[m] = Field3(std::string(names[m]), g.sx(), g.sy(), g.sz());
    now_[m] = Field3(std::string(names[m]) + "_rhs_now", g.sx(), g.sy(), g.sz());
    before_[m] = Field3(std::string(names[m]) + "_rhs_before", g.sx(), g.sy(), g.sz());
  }
  inside_ = Field3("xi_inside", g.sx(), g.sy(), g.sz());
}

void ReferenceMap::fill_ghosts(const Grid& g, Halo& halo) const {
  halo.exchange({xi_[0], xi_[1], xi_[2]});
  // walls: even reflection, as phi and B (the particle never reaches them)
  const int ng = Grid::ng, ny = g.ny;
  const Field3 x0 = xi_[0], x1 = xi_[1], x2 = xi_[2];
  par_for(
      "refmap_walls", Range3{0, g.sx(), 0, ng, 0, g.sz()}, KOKKOS_LAMBDA(int i, int m, int k) {
        x0(i, ng - 1 - m, k) = x0(i, ng + m, k);
        x1(i, ng - 1 - m, k) = x1(i, ng + m, k);
        x2(i, ng - 1 - m, k) = x2(i, ng + m, k);
        x0(i, ng + ny + m, k) = x0(i, ng + ny - 1 - m, k);
        x1(i, ng + ny + m, k) = x1(i, ng + ny - 1 - m, k);
        x2(i, ng + ny + m, k) = x2(i, ng + ny - 1 - m, k);
      });
}

void ReferenceMap::resume(const Grid& g, Halo& halo) {
  work_ = g.interior();  // until begin_step
  fill_ghosts(g, halo);
  halo.exchange({inside_});
  prior_ = mean_gradient(
      g, [&halo](Real* x, int n) { MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, halo.comm()); });
}

void ReferenceMap::begin_step(const Grid& g, MPI_Comm comm, bool whole) {
  const Range3 in = g.interior();
  if (whole) {
    work_ = in;
    return;
  }
  // the inside cells' box in global indices (a rank sees only its part)
  const Field3 inside = inside_;
  const int ng = Grid::ng, x0 = g.x0, z0 = g.z0;
  IndexBox box;
  par_reduce(
      "refmap_work_box", in,
      KOKKOS_LAMBDA(int i, int j, int k, IndexBox& b) {
        if (inside(i, j, k) == 0) return;
        const int c[3] = {x0 + i - ng, j - ng, z0 + k - ng};
        for (int d = 0; d < 3; ++d) {
          b.lo[d] = c[d] < b.lo[d] ? c[d] : b.lo[d];
          b.hi[d] = c[d] > b.hi[d] ? c[d] : b.hi[d];
        }
      },
      BoxUnion(box));
  int ext[6] = {-box.lo[0], -box.lo[1], -box.lo[2], box.hi[0], box.hi[1], box.hi[2]};
  MPI_Allreduce(MPI_IN_PLACE, ext, 6, MPI_INT, MPI_MAX, comm);
  const Range3 none{in.ib, in.ib, in.jb, in.jb, in.kb, in.kb};
  if (-ext[0] > ext[3]) {  // no cell maps inside
    work_ = none;
    return;
  }
  // grown, in global half-open intervals; x and z are periodic, and a box
  // that would cross their seam takes the whole extent (the box of a
  // particle on the seam spans it anyway: its cells lie at both ends)
  const int n[3] = {g.nx, g.ny, g.nz}, margin = work_margin(correction_passes_);
  int lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = -ext[d] - margin;
    hi[d] = ext[3 + d] + 1 + margin;
    if (d != 1 && (lo[d] < 0 || hi[d] > n[d])) lo[d] = 0, hi[d] = n[d];
  }
  const Range3 local{lo[0] - x0 + ng, hi[0] - x0 + ng, lo[1] + ng,
                     hi[1] + ng,      lo[2] - z0 + ng, hi[2] - z0 + ng};
  work_ = grown(local, 0, in);
  if (work_.empty()) work_ = none;
}

void ReferenceMap::seed(const Grid& g, Halo& halo, const FaceFluxes& scratch) {
  const Field3 x0 = xi_[0], x1 = xi_[1], x2 = xi_[2];
  const Grid gg = g;
  par_for(
      "refmap_seed", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        x0(i, j, k) = gg.xc(i);
        x1(i, j, k) = gg.yc(j);
        x2(i, j, k) = gg.zc(k);
      });
  for (int m = 0; m < 3; ++m) Kokkos::deep_copy(before_[m], 0.0);
  work_ = g.interior();  // every cell holds the far value after this refit, or a band or inside one
  fill_ghosts(g, halo);
  mark_inside(xi_, c_, r_, inside_);
  refit_band(g, halo, scratch);
}

void ReferenceMap::advance_stage(const Grid& g, const FlowState& flow, const FaceFluxes& flux, Real gdt,
                                 Real zdt, Halo& halo) {
  // u . grad xi = div(u xi) for the projected (discretely divergence-free)
  // velocity: the transport's flux form with WENO5 face values
  const Range3 work = work_;
  if (!work.empty())  // else no cell of this rank is near the particle this step
    for (int m = 0; m < 3; ++m) phi_transport_rhs(g, flow, xi_[m], now_[m], flux, work, PhiScheme{});
  for (int m = 0; m < 3; ++m) {
    const Field3 q = xi_[m], a = now_[m], b = before_[m];
    par_for(
        "refmap_rk3_update", work,
        KOKKOS_LAMBDA(int i, int j, int k) { q(i, j, k) += gdt * a(i, j, k) + zdt * b(i, j, k); });
    std::swap(now_[m], before_[m]);
  }
  fill_ghosts(g, halo);
  refit_band(g, halo, flux);
}

// Layer by layer, as a marching extension: the cells next to the valid ones
// (first those mapping inside) are fitted from the valid cells within 3, then
// count as valid. A cell three out fitted from the inside cells alone would
// see only a thin cap of them, too flat to fix an affine map.
void ReferenceMap::refit_band(const Grid& g, Halo& halo, const FaceFluxes& scratch) {
  const Field3 valid = scratch.z, next = scratch.x, inside = inside_;
  const auto allreduce_sum = [&halo](Real* x, int n) {
    MPI_Allreduce(MPI_IN_PLACE, x, n, MPI_DOUBLE, MPI_SUM, halo.comm());
  };
  // a cell maps inside only next to one that did before the stage (the
  // interface moves less than a cell in one): a cell at the band's edge can
  // take a value mixed with the far value's that happens to map inside
  mark_inside(xi_, c_, r_, valid);
  mark_near(inside, 0.5, 1, work_, scratch.x, scratch.y, next);
  par_for(
      "refmap_inside_kept", work_, KOKKOS_LAMBDA(int i, int j, int k) {
        const Real v = valid(i, j, k) != 0 && next(i, j, k) != 0 ? Real(1) : Real(0);
        valid(i, j, k) = v;
        inside(i, j, k) = v;
      });
  halo.exchange({valid, inside});
  prior_ = mean_gradient(g, allreduce_sum);
  const GradientPrior prior = prior_;
  const Field3 x0 = xi_[0], x1 = xi_[1], x2 = xi_[2];
  const Real c0 = c_[0], c1 = c_[1], c2 = c_[2], r = r_, edge = soft_edge_cells * g.dx;
  for (int layer = 1; layer <= band_layers; ++layer) {
    const bool first = layer == 1;
    mark_near(valid, 0.5, 1, work_, scratch.x, scratch.y, next);
    // a layer's cell reads only valid cells, which this pass does not write
    par_for(
        "refmap_band", work_, KOKKOS_LAMBDA(int i, int j, int k) {
          if (valid(i, j, k) != 0 || next(i, j, k) == 0) return;
          AffineFit fit;
          Real mean[3] = {0, 0, 0}, wsum = 0;
          constexpr int R = fit_reach;
          for (int c = -R; c <= R; ++c)
            for (int b = -R; b <= R; ++b)
              for (int a = -R; a <= R; ++a) {
                if (valid(i + a, j + b, k + c) == 0) continue;
                const Real o[3] = {Real(a), Real(b), Real(c)};  // in cells: a well-scaled system
                const Real v[3] = {x0(i + a, j + b, k + c), x1(i + a, j + b, k + c), x2(i + a, j + b, k + c)};
                const Real w = Real(1) / Real(a * a + b * b + c * c);  // the nearer, the more
                fit.add(o, v, w);
                for (int m = 0; m < 3; ++m) mean[m] += w * v[m];
                wsum += w;
              }
          fit.prior(prior.G, ridge * wsum);
          Real out[3];
          if (!fit.solve(out))
            for (int m = 0; m < 3; ++m) out[m] = mean[m] / wsum;  // too few cells to span 3-D
          const Real own[3] = {x0(i, j, k), x1(i, j, k), x2(i, j, k)};
          const Real q[3] = {own[0] - c0, own[1] - c1, own[2] - c2};
          const Real kept = first ? soft_edge_weight(q, r, edge) : Real(0);
          for (int m = 0; m < 3; ++m) out[m] += kept * (own[m] - out[m]);
          x0(i, j, k) = out[0], x1(i, j, k) = out[1], x2(i, j, k) = out[2];
        });
    par_for(
        "refmap_band_valid", work_, KOKKOS_LAMBDA(int i, int j, int k) {
          if (next(i, j, k) != 0) valid(i, j, k) = 1;
        });
    fill_ghosts(g, halo);
    halo.exchange({valid});
  }
  const Real far0 = c_[0] + far_offset * r_, far1 = c_[1] + far_offset * r_, far2 = c_[2] + far_offset * r_;
  par_for(
      "refmap_far", work_, KOKKOS_LAMBDA(int i, int j, int k) {
        if (valid(i, j, k) == 0) x0(i, j, k) = far0, x1(i, j, k) = far1, x2(i, j, k) = far2;
      });
  fill_ghosts(g, halo);
}

Real ReferenceMap::correct_volume(const Grid& g, PoissonSolver& poisson, Halo& halo,
                                  const FaceFluxes& scratch) {
  const MapGradient grad(xi_, g);
  const Field3 inside = inside_, s = scratch.y, psi = scratch.x;
  // s = 1 - 1 / det J in the inside cells, and their largest det B error
  // (infinite where the map is broken, det J <= 0: no source there, since
  // a potential displacement cannot unfold it); then their sum and count
  Real sums[2] = {0, 0}, worst = 0;
  par_reduce(
      "refmap_volume_source", work_,
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        Real J[3][3], F[3][3];
        grad(i, j, k, J);
        const Real det = invert_map_gradient(J, F);
        const bool in = inside(i, j, k) != 0;
        s(i, j, k) = in && det > 0 ? 1 - 1 / det : Real(0);
        if (!in) return;
        const Real e =
            det > 0 ? Kokkos::fabs(1 / (det * det) - 1) : Kokkos::Experimental::infinity<Real>::value;
        a = e > a ? e : a;
      },
      Kokkos::Max<Real>(worst));
  par_reduce(
      "refmap_volume_source_sum", work_, KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a += s(i, j, k); },
      Kokkos::Sum<Real>(sums[0]));
  par_reduce(
      "refmap_volume_inside_count", work_,
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a += inside(i, j, k); }, Kokkos::Sum<Real>(sums[1]));
  MPI_Allreduce(MPI_IN_PLACE, sums, 2, MPI_DOUBLE, MPI_SUM, halo.comm());
  MPI_Allreduce(MPI_IN_PLACE, &worst, 1, MPI_DOUBLE, MPI_MAX, halo.comm());
  const Real cells = Real(g.nx) * g.ny * g.nz;
  if (sums[1] == 0 || sums[1] == cells) return worst;
  // the source's sum, sunk evenly in the fluid (the walls are Neumann): the
  // map's total volume is corrected too, and the fluid's xi is never read
  const Real sink = -sums[0] / (cells - sums[1]);
  const Array1 rhs = poisson.rhs();
  const int ng = Grid::ng, ny = g.ny, nxl = g.nxl;
  par_for(
      "refmap_volume_rhs", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        rhs(PoissonSolver::index(i - ng, j - ng, k - ng, ny, nxl)) = inside(i, j, k) != 0 ? s(i, j, k) : sink;
      });
  poisson.solve();
  poisson_to_field(g, rhs, psi);
  halo.exchange({psi});
  apply_pressure_walls(g, psi);
  // xi(x - d) = xi - J d, d = grad psi (central): into now_ (free after the
  // stage's swap). Every cell moves, the band's too: a band cell at the soft
  // edge keeps part of its value through the refit below (which resets the
  // cells beyond the band to the far value)
  const Field3 x0 = xi_[0], x1 = xi_[1], x2 = xi_[2], d0 = now_[0], d1 = now_[1], d2 = now_[2];
  const CentralGradient grad_psi(psi, g);
  par_for(
      "refmap_volume_shift", work_, KOKKOS_LAMBDA(int i, int j, int k) {
        Real J[3][3], d[3];
        grad(i, j, k, J);
        grad_psi(i, j, k, d);
        d0(i, j, k) = J[0][0] * d[0] + J[0][1] * d[1] + J[0][2] * d[2];
        d1(i, j, k) = J[1][0] * d[0] + J[1][1] * d[1] + J[1][2] * d[2];
        d2(i, j, k) = J[2][0] * d[0] + J[2][1] * d[1] + J[2][2] * d[2];
      });
  par_for(
      "refmap_volume_apply", work_, KOKKOS_LAMBDA(int i, int j, int k) {
        x0(i, j, k) -= d0(i, j, k);
        x1(i, j, k) -= d1(i, j, k);
        x2(i, j, k) -= d2(i, j, k);
      });
  fill_ghosts(g, halo);
  refit_band(g, halo, scratch);
  return worst;
}

GradientPrior ReferenceMap::mean_gradient(const Grid& g,
                                          const std::function<void(Real*, int)>& allreduce_sum) const {
  const Field3 inside = inside_;
  const Range3 cells = work_;
  Real sums[12];  // 9 sums of differences, then the pairs per axis
  for (int b = 0; b < 3; ++b) {
    const int di = b == 0, dj = b == 1, dk = b == 2;
    for (int m = 0; m <= 3; ++m) {
      const Field3 x = m < 3 ? xi_[m] : inside_;
      const bool count = m == 3;
      Real s = 0;
      par_reduce(
          "refmap_mean_gradient", cells,
          KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
            if (inside(i, j, k) == 0 || inside(i + di, j + dj, k + dk) == 0) return;
            a += count ? Real(1) : x(i + di, j + dj, k + dk) - x(i, j, k);
          },
          Kokkos::Sum<Real>(s));
      sums[m < 3 ? 3 * m + b : 9 + b] = s;
    }
  }
  allreduce_sum(sums, 12);
  GradientPrior p;
  const Real h[3] = {g.dx, g.dy, g.dz};  // xi = x where no pair says otherwise
  for (int m = 0; m < 3; ++m)
    for (int b = 0; b < 3; ++b) p.G[m][b] = sums[9 + b] > 0 ? sums[3 * m + b] / sums[9 + b] : (m == b) * h[b];
  return p;
}

Real ReferenceMap::solid_from_map(const Grid& g, const SolidFields& f, const FaceFluxes& scratch,
                                  const std::function<void(Real*, int)>& allreduce_sum) const {
  const Field3 near = scratch.x, inside = inside_;
  // the band's refit took it from the same inside cells (the refit writes only outside ones)
  const GradientPrior prior = prior_;
  mark_near(inside_, 0.5, solid_reach, work_, scratch.x, scratch.y, near);
  const MapGradient grad(xi_, g);
  const Field3 x0 = xi_[0], x1 = xi_[1], x2 = xi_[2];
  const Real c0 = c_[0], c1 = c_[1], c2 = c_[2], r = r_;
  const Real h0 = g.dx, h1 = g.dy, h2 = g.dz;
  const SolidViews q(f);
  par_for(
      "refmap_phi", work_, KOKKOS_LAMBDA(int i, int j, int k) {
        if (near(i, j, k) == 0) {
          q.phi(i, j, k) = 0;
          q.b0(i, j, k) = q.b3(i, j, k) = q.b5(i, j, k) = 1;
          q.b1(i, j, k) = q.b2(i, j, k) = q.b4(i, j, k) = 0;
          return;
        }
        Real J[3][3];
        const Real h[3] = {h0, h1, h2};
        if (inside(i, j, k) != 0 || !fitted_gradient(inside, x0, x1, x2, h, prior, i, j, k, J))
          grad(i, j, k, J);
        const Real d[3] = {x0(i, j, k) - c0, x1(i, j, k) - c1, x2(i, j, k) - c2};
        const Real p = reference_ball_share(d, J, r, h, share_samples);
        q.phi(i, j, k) = p;
        Real B[6] = {1, 0, 0, 1, 0, 1};
        if (p > 0) b_from_map_gradient(J, B);
        for (int m = 0; m < 6; ++m) q.field(1 + m)(i, j, k) = B[m];
      });
  // the sphere's volume, to round-off: the sum's error into the interface
  // cells in proportion to phi (1 - phi), as phi_bounded_redistribution
  Real sums[2] = {0, 0};
  par_reduce(
      "refmap_volume", work_, KOKKOS_LAMBDA(int i, int j, int k, Real& s) { s += kept_phi(q.phi(i, j, k)); },
      Kokkos::Sum<Real>(sums[0]));
  par_reduce(
      "refmap_interface_weight", work_,
      KOKKOS_LAMBDA(int i, int j, int k, Real& s) { s += interface_weight(q.phi(i, j, k), phi_zero_cut); },
      Kokkos::Sum<Real>(sums[1]));
  allreduce_sum(sums, 2);
  const Real e = volume_ - sums[0];
  const Real a = redistribution_coefficient(e, sums[1]);
  par_for(
      "refmap_phi_volume", work_, KOKKOS_LAMBDA(int i, int j, int k) {
        q.phi(i, j, k) = redistributed_phi(q.phi(i, j, k), a, phi_zero_cut);
      });
  return volume_ > 0 ? e / volume_ : Real(0);
}

}  // namespace softflow
