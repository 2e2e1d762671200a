#include "diagnostics.hpp"
#include "../kernels/solid_state.hpp"

#include <cmath>

#include "../kernels/projection.hpp"

namespace softflow {

namespace {
constexpr int q_u = 0, q_shear = 1, q_count = 2;
}

Diagnostics::Diagnostics(FlowSolver& s)
    : s_(s),
      sums_("diag_plane_sums", s.grid().ny + 1, q_count),
      host_("diag_plane_sums_host", s.grid().ny + 1, q_count) {}

// Row r of the plane sums: q_u at cell row r (r < ny), q_shear at y-face
// r - 1/2 counted from the bottom wall (r = 0 bottom wall, r = ny top wall).
void Diagnostics::plane_sums() {
  const Grid g = s_.grid();
  auto u = s_.state().u, v = s_.state().v;
  auto sums = sums_;
  const Real mu = s_.config().fluid.mu, idx = 1 / g.dx, idy = 1 / g.dy;
  const int nxl = g.nxl, nzl = g.nzl, ng = Grid::ng, ny = g.ny;
  using Team = Kokkos::TeamPolicy<ExecSpace>;
  Kokkos::parallel_for(
      "diagnostics_plane_sums", Team(ny + 1, Kokkos::AUTO), KOKKOS_LAMBDA(const Team::member_type& t) {
        const int r = t.league_rank();
        Real su = 0, ss = 0;
        Kokkos::parallel_reduce(
            Kokkos::TeamThreadRange(t, nxl * nzl),
            [&](int m, Real& a) {
              const int i = ng + m % nxl, k = ng + m / nxl;
              if (r < ny) a += 0.5 * (u(i, ng + r, k) + u(i - 1, ng + r, k));
            },
            su);
        Kokkos::parallel_reduce(
            Kokkos::TeamThreadRange(t, nxl * nzl),
            [&](int m, Real& a) {
              const int i = ng + m % nxl, k = ng + m / nxl, jf = ng - 1 + r;
              a += mu * ((u(i, jf + 1, k) - u(i, jf, k)) * idy + (v(i + 1, jf, k) - v(i, jf, k)) * idx);
            },
            ss);
        Kokkos::single(Kokkos::PerTeam(t), [&]() {
          sums(r, q_u) = su;
          sums(r, q_shear) = ss;
        });
      });
  Kokkos::deep_copy(host_, sums_);
  MPI_Allreduce(MPI_IN_PLACE, host_.data(), int(host_.size()), MPI_DOUBLE, MPI_SUM,
                s_.decomposition().comm);
}

FlowProfiles Diagnostics::profiles() {
  plane_sums();
  const Grid& g = s_.grid();
  const Real n = Real(g.nx) * g.nz;
  FlowProfiles p;
  for (int j = 0; j < g.ny; ++j) {
    p.y_centre.push_back(g.yc(Grid::ng + j));
    p.u_mean.push_back(host_(j, q_u) / n);
  }
  for (int r = 0; r <= g.ny; ++r) {
    p.y_face.push_back(-g.h() + r * g.dy);
    p.shear.push_back(host_(r, q_shear) / n);
  }
  return p;
}

FlowScalars Diagnostics::scalars() {
  FlowScalars f;
  FlowProfiles p = profiles();
  f.tau_bottom = p.shear.front();
  f.tau_top = p.shear.back();
  const Real gamma = s_.config().shear_rate();
  if (gamma != 0) f.mu_eff = 0.5 * (f.tau_bottom + f.tau_top) / (s_.config().fluid.mu * gamma);

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
  auto detb = KOKKOS_LAMBDA(int i, int j, int k) {
    const Real xx = q.b0(i, j, k), xy = q.b1(i, j, k), xz = q.b2(i, j, k), yy = q.b3(i, j, k),
               yz = q.b4(i, j, k), zz = q.b5(i, j, k);
    return xx * (yy * zz - yz * yz) - xy * (xy * zz - yz * xz) + xz * (xy * yz - yy * xz);
  };
  par_reduce(
      "diagnostics_detb_min", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        if (q.phi(i, j, k) > 0.5) a = Kokkos::fmin(a, detb(i, j, k));
      },
      Kokkos::Min<Real>(dmin));
  par_reduce(
      "diagnostics_detb_max", g.interior(),
      KOKKOS_LAMBDA(int i, int j, int k, Real& a) {
        if (q.phi(i, j, k) > 0.5) a = Kokkos::fmax(a, detb(i, j, k));
      },
      Kokkos::Max<Real>(dmax));
  MPI_Comm c = s_.decomposition().comm;
  MPI_Allreduce(MPI_IN_PLACE, &vol, 1, MPI_DOUBLE, MPI_SUM, c);
  MPI_Allreduce(MPI_IN_PLACE, &pmin, 1, MPI_DOUBLE, MPI_MIN, c);
  MPI_Allreduce(MPI_IN_PLACE, &pmax, 1, MPI_DOUBLE, MPI_MAX, c);
  MPI_Allreduce(MPI_IN_PLACE, &dmin, 1, MPI_DOUBLE, MPI_MIN, c);
  MPI_Allreduce(MPI_IN_PLACE, &dmax, 1, MPI_DOUBLE, MPI_MAX, c);
  f.solid_volume = vol * g.dx * g.dy * g.dz;
  f.phi_min = pmin;
  f.phi_max = pmax;
  // no solid cell anywhere: report the neutral value
  f.detb_min = dmin > 1e300 ? 1 : dmin;
  f.detb_max = dmax < -1e300 ? 1 : dmax;
}

}  // namespace softflow
