#include "diagnostics.hpp"
#include "../kernels/solid_state.hpp"

#include <cmath>
#include <utility>

#include "../kernels/mixture_stress.hpp"
#include "../kernels/projection.hpp"
#include "../kernels/solid_extension.hpp"

namespace softflow {

namespace {
// the plane sums of one row: cell-centre quantities of cell row r, face
// quantities of the y-face below it (r = ny: the top wall)
enum RowQuantity { q_u, q_phi, q_fv, q_pv, q_el, q_uv_f, q_v_f, q_uv_p, q_v_p, q_count };
}  // namespace

namespace detail {
// N sums reduced in one pass (Kokkos::Sum of a small array)
template <int N>
struct Sums {
  Real q[N];
  KOKKOS_INLINE_FUNCTION Sums() {
    for (int m = 0; m < N; ++m) q[m] = 0;
  }
  KOKKOS_INLINE_FUNCTION Sums& operator+=(const Sums& o) {
    for (int m = 0; m < N; ++m) q[m] += o.q[m];
    return *this;
  }
};
using RowSums = Sums<q_count>;
}  // namespace detail
}  // namespace softflow

template <int N>
struct Kokkos::reduction_identity<softflow::detail::Sums<N>> {
  KOKKOS_FORCEINLINE_FUNCTION static softflow::detail::Sums<N> sum() { return {}; }
};

namespace softflow {

const char* budget_name(int term) {
  static const char* names[n_budget] = {"fluid_viscous", "particle_viscous", "particle_elastic",
                                        "fluid_reynolds", "particle_reynolds"};
  return names[term];
}

Diagnostics::Diagnostics(FlowSolver& s)
    : s_(s),
      sums_("diag_plane_sums", s.grid().ny + 1, q_count),
      host_("diag_plane_sums_host", s.grid().ny + 1, q_count) {}

void Diagnostics::plane_sums() {
  using detail::RowSums;
  const Grid g = s_.grid();
  const Config& c = s_.config();
  auto u = s_.state().u, v = s_.state().v;
  const bool solid = s_.solid() != nullptr;
  const Field3 phi = solid ? s_.solid()->fields().q[0] : Field3();
  const Field3 b12 = solid ? s_.solid()->fields().q[2] : Field3();
  auto sums = sums_;
  const Real mu_f = c.fluid.mu, mu_s = c.fluid.mu * (solid ? c.particles.viscosity_ratio : 1);
  const Real G = solid ? c.shear_modulus() : 0;
  const Real idx = 1 / g.dx, idy = 1 / g.dy;
  const int nxl = g.nxl, nzl = g.nzl, ng = Grid::ng, ny = g.ny;
  using Team = Kokkos::TeamPolicy<ExecSpace>;
  Kokkos::parallel_for(
      "diagnostics_plane_sums", Team(ny + 1, Kokkos::AUTO), KOKKOS_LAMBDA(const Team::member_type& t) {
        const int r = t.league_rank();
        RowSums row;
        Kokkos::parallel_reduce(
            Kokkos::TeamThreadRange(t, nxl * nzl),
            [&](int m, RowSums& a) {
              const int i = ng + m % nxl, k = ng + m / nxl, jc = ng + r, jf = ng - 1 + r;
              if (r < ny) {
                a.q[q_u] += 0.5 * (u(i, jc, k) + u(i - 1, jc, k));
                if (solid) a.q[q_phi] += fraction(phi(i, jc, k));
              }
              // the x-y edge (i + 1/2, jf + 1/2)
              const Real s12 = (u(i, jf + 1, k) - u(i, jf, k)) * idy + (v(i + 1, jf, k) - v(i, jf, k)) * idx;
              const Real ue = 0.5 * (u(i, jf, k) + u(i, jf + 1, k)),
                         ve = 0.5 * (v(i, jf, k) + v(i + 1, jf, k));
              Real pe = 0, be = 0;
              if (solid) {
                const Real p00 = fraction(phi(i, jf, k)), p10 = fraction(phi(i + 1, jf, k)),
                           p01 = fraction(phi(i, jf + 1, k)), p11 = fraction(phi(i + 1, jf + 1, k));
                pe = 0.25 * (p00 + p10 + p01 + p11);
                be = 0.25 * (p00 * b12(i, jf, k) + p10 * b12(i + 1, jf, k) + p01 * b12(i, jf + 1, k) +
                             p11 * b12(i + 1, jf + 1, k));
              }
              a.q[q_fv] += (1 - pe) * mu_f * s12;
              a.q[q_pv] += pe * mu_s * s12;
              a.q[q_el] += G * be;
              a.q[q_uv_f] += (1 - pe) * ue * ve;
              a.q[q_v_f] += (1 - pe) * ve;
              a.q[q_uv_p] += pe * ue * ve;
              a.q[q_v_p] += pe * ve;
            },
            Kokkos::Sum<RowSums>(row));
        Kokkos::single(Kokkos::PerTeam(t), [&]() {
          for (int m = 0; m < q_count; ++m) sums(r, m) = row.q[m];
        });
      });
  Kokkos::deep_copy(host_, sums_);
  MPI_Allreduce(MPI_IN_PLACE, host_.data(), int(host_.size()), MPI_DOUBLE, MPI_SUM, s_.decomposition().comm);
}

FlowProfiles Diagnostics::profiles() {
  plane_sums();
  const Grid& g = s_.grid();
  const Real n = Real(g.nx) * g.nz, rho = s_.config().fluid.rho;
  FlowProfiles p;
  for (std::vector<Real>* v : {&p.y_centre, &p.u_mean, &p.phi_mean}) v->reserve(g.ny);
  for (std::vector<Real>* v : {&p.y_face, &p.shear}) v->reserve(g.ny + 1);
  for (std::vector<Real>& v : p.budget) v.reserve(g.ny + 1);
  for (int j = 0; j < g.ny; ++j) {
    p.y_centre.push_back(g.yc(Grid::ng + j));
    p.u_mean.push_back(host_(j, q_u) / n);
    p.phi_mean.push_back(host_(j, q_phi) / n);
  }
  for (int r = 0; r <= g.ny; ++r) {
    p.y_face.push_back(-g.h() + r * g.dy);
    // <u> on the face; on the walls v = 0 and the Reynolds sums vanish anyway
    const Real uf = (r == 0 || r == g.ny) ? 0 : 0.5 * (p.u_mean[r - 1] + p.u_mean[r]);
    p.budget[fluid_viscous].push_back(host_(r, q_fv) / n);
    p.budget[particle_viscous].push_back(host_(r, q_pv) / n);
    p.budget[particle_elastic].push_back(host_(r, q_el) / n);
    p.budget[fluid_reynolds].push_back(-rho * (host_(r, q_uv_f) - uf * host_(r, q_v_f)) / n);
    p.budget[particle_reynolds].push_back(-rho * (host_(r, q_uv_p) - uf * host_(r, q_v_p)) / n);
    p.shear.push_back(p.budget[fluid_viscous].back() + p.budget[particle_viscous].back() +
                      p.budget[particle_elastic].back());
  }
  return p;
}

void Diagnostics::normal_stress_differences(Real& n1, Real& n2, Real& n1_elastic) {
  const Grid g = s_.grid();
  const Config& c = s_.config();
  auto u = s_.state().u, v = s_.state().v, w = s_.state().w;
  const bool solid = s_.solid() != nullptr;
  const Field3 phi = solid ? s_.solid()->fields().q[0] : Field3();
  const Field3 bxx = solid ? s_.solid()->fields().q[1] : Field3();
  const Field3 byy = solid ? s_.solid()->fields().q[4] : Field3();
  const Field3 bzz = solid ? s_.solid()->fields().q[6] : Field3();
  const Real mu_f = c.fluid.mu, dmu = solid ? c.fluid.mu * (c.particles.viscosity_ratio - 1) : 0;
  const Real G = solid ? c.shear_modulus() : 0;
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  // sigma_11 - sigma_22 and sigma_22 - sigma_33 at the cell centres, in one pass
  detail::Sums<3> sums;
  par_reduce(
      "diagnostics_normal_stress_differences", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, detail::Sums<3>& a) {
        const Real f = solid ? fraction(phi(i, j, k)) : Real(0), mu = mu_f + dmu * f;
        Real s11 = 2 * mu * (u(i, j, k) - u(i - 1, j, k)) * idx;
        Real s22 = 2 * mu * (v(i, j, k) - v(i, j - 1, k)) * idy;
        Real s33 = 2 * mu * (w(i, j, k) - w(i, j, k - 1)) * idz;
        if (solid) {
          s11 += G * f * (bxx(i, j, k) - 1);
          s22 += G * f * (byy(i, j, k) - 1);
          s33 += G * f * (bzz(i, j, k) - 1);
          a.q[2] += G * f * (bxx(i, j, k) - byy(i, j, k));
        }
        a.q[0] += s11 - s22;
        a.q[1] += s22 - s33;
      },
      Kokkos::Sum<detail::Sums<3>>(sums));
  Real b[3] = {sums.q[0], sums.q[1], sums.q[2]};
  MPI_Allreduce(MPI_IN_PLACE, b, 3, MPI_DOUBLE, MPI_SUM, s_.decomposition().comm);
  const Real cells = Real(g.cells_global());
  n1 = b[0] / cells, n2 = b[1] / cells, n1_elastic = b[2] / cells;
}

FlowScalars Diagnostics::scalars(FlowProfiles* profiles_out) {
  FlowScalars f;
  FlowProfiles p = profiles();
  f.tau_bottom = p.shear.front();
  f.tau_top = p.shear.back();
  const Real gamma = s_.config().shear_rate();
  const Real unit = gamma != 0 ? s_.config().fluid.mu * gamma : Real(1);  // mu_f gamma
  if (gamma != 0) f.mu_eff = 0.5 * (f.tau_bottom + f.tau_top) / unit;
  // gap averages of the budget (trapezoid over the faces, walls weighted 1/2)
  Real* avg[n_budget] = {&f.fluid_viscous, &f.particle_viscous, &f.particle_elastic, &f.fluid_reynolds,
                         &f.particle_reynolds};
  for (int b = 0; b < n_budget; ++b) {
    const auto& prof = p.budget[b];
    Real sum = 0;
    for (size_t r = 0; r < prof.size(); ++r) sum += (r == 0 || r + 1 == prof.size() ? 0.5 : 1.0) * prof[r];
    *avg[b] = sum / Real(prof.size() - 1) / unit;
  }
  normal_stress_differences(f.n1, f.n2, f.n1_elastic);
  f.n1 /= unit, f.n2 /= unit, f.n1_elastic /= unit;
  if (profiles_out) *profiles_out = std::move(p);

  const Grid g = s_.grid();
  auto u = s_.state().u, v = s_.state().v, w = s_.state().w;
  const Real idx = 1 / g.dx, idy = 1 / g.dy, idz = 1 / g.dz;
  Real ke = 0, div = 0, speed = 0;
  par_reduce(
      "diagnostics_kinetic_energy", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        const Real uc = 0.5 * (u(i, j, k) + u(i - 1, j, k));
        const Real vc = 0.5 * (v(i, j, k) + v(i, j - 1, k));
        const Real wc = 0.5 * (w(i, j, k) + w(i, j, k - 1));
        a += 0.5 * (uc * uc + vc * vc + wc * wc);
      },
      Kokkos::Sum<Real>(ke));
  par_reduce(
      "diagnostics_max_divergence", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        const Real d = Kokkos::fabs(divergence(u, v, w, i, j, k, idx, idy, idz));
        a = d > a ? d : a;
      },
      Kokkos::Max<Real>(div));
  par_reduce(
      "diagnostics_max_speed", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        const Real m = Kokkos::fmax(Kokkos::fabs(u(i, j, k)),
                                    Kokkos::fmax(Kokkos::fabs(v(i, j, k)), Kokkos::fabs(w(i, j, k))));
        a = m > a ? m : a;
      },
      Kokkos::Max<Real>(speed));
  MPI_Comm c = s_.decomposition().comm;
  MPI_Allreduce(MPI_IN_PLACE, &ke, 1, MPI_DOUBLE, MPI_SUM, c);
  MPI_Allreduce(MPI_IN_PLACE, &div, 1, MPI_DOUBLE, MPI_MAX, c);
  MPI_Allreduce(MPI_IN_PLACE, &speed, 1, MPI_DOUBLE, MPI_MAX, c);
  f.kinetic_energy = ke / Real(g.cells_global());
  f.max_div = div;
  f.max_speed = speed;
  if (s_.solid()) solid_scalars(f);
  return f;
}

void Diagnostics::solid_scalars(FlowScalars& f) {
  const Grid g = s_.grid();
  const SolidViews q(s_.solid()->fields());
  Real vol = 0, pmin = 0, pmax = 0, dmin = 0, dmax = 0;
  par_reduce(
      "diagnostics_solid_volume", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a += q.phi(i, j, k); }, Kokkos::Sum<Real>(vol));
  par_reduce(
      "diagnostics_phi_min", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a = Kokkos::fmin(a, q.phi(i, j, k)); },
      Kokkos::Min<Real>(pmin));
  par_reduce(
      "diagnostics_phi_max", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) { a = Kokkos::fmax(a, q.phi(i, j, k)); },
      Kokkos::Max<Real>(pmax));
  {
    // the same range the det B projection measures (kernels/solid_extension.hpp)
    const Kokkos::MinMaxScalar<Real> mm = det_b_range(s_.solid()->fields(), g.interior());
    dmin = mm.min_val;
    dmax = mm.max_val;
  }
  // in one pass: phi B_xy over phi < 0.1 cells, over all cells, and phi over
  // phi < 0.1 cells (solid that has left the particles as thin wisps; the total is vol)
  detail::Sums<3> lows;
  par_reduce(
      "diagnostics_solid_lowphi", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, detail::Sums<3>& a) {
        const Real p = q.phi(i, j, k), sb = fraction(p) * q.b1(i, j, k);
        a.q[1] += sb;
        if (p < 0.1) a.q[0] += sb, a.q[2] += p;
      },
      Kokkos::Sum<detail::Sums<3>>(lows));
  MPI_Comm c = s_.decomposition().comm;
  MPI_Allreduce(MPI_IN_PLACE, lows.q, 3, MPI_DOUBLE, MPI_SUM, c);
  f.elastic_share_lowphi = lows.q[1] != 0 ? lows.q[0] / lows.q[1] : 0;
  const SolidPhase::BStats b = s_.solid()->take_b_stats();
  f.unimodular_removed = b.stages > 0 ? b.removed_sum / Real(b.stages) : 0;
  f.map_det_corrected = b.map_det_corrected;
  f.map_volume_moved = b.map_volume_moved;
  f.debris_returned = b.debris_returned;
  long fallback = b.fallback_cells;
  MPI_Allreduce(MPI_IN_PLACE, &fallback, 1, MPI_LONG, MPI_SUM, s_.decomposition().comm);
  f.b_fallback_cells = fallback;
  MPI_Allreduce(MPI_IN_PLACE, &vol, 1, MPI_DOUBLE, MPI_SUM, c);
  MPI_Allreduce(MPI_IN_PLACE, &pmin, 1, MPI_DOUBLE, MPI_MIN, c);
  MPI_Allreduce(MPI_IN_PLACE, &pmax, 1, MPI_DOUBLE, MPI_MAX, c);
  MPI_Allreduce(MPI_IN_PLACE, &dmin, 1, MPI_DOUBLE, MPI_MIN, c);
  MPI_Allreduce(MPI_IN_PLACE, &dmax, 1, MPI_DOUBLE, MPI_MAX, c);
  f.solid_volume = vol * g.dx * g.dy * g.dz;
  f.solid_share_lowphi = vol != 0 ? lows.q[2] / vol : 0;
  f.phi_min = pmin;
  f.phi_max = pmax;
  // no solid cell anywhere: report the neutral value
  f.detb_min = dmin > 1e300 ? 1 : dmin;
  f.detb_max = dmax < -1e300 ? 1 : dmax;
  // no stage since the last row (the first row): the current range
  f.detb_raw_min = b.det_min > b.det_max ? f.detb_min : b.det_min;
  f.detb_raw_max = b.det_min > b.det_max ? f.detb_max : b.det_max;
}

}  // namespace softflow
