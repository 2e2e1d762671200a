#include "particle_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "../kernels/mixture_stress.hpp"

namespace softflow {

namespace {

// eigenvalues of a symmetric 3x3 matrix (Jacobi rotations), descending
void eig3(double m[3][3], double ev[3]) {
  for (int sweep = 0; sweep < 50; ++sweep) {
    double off = m[0][1] * m[0][1] + m[0][2] * m[0][2] + m[1][2] * m[1][2];
    if (off < 1e-30) break;
    for (int p = 0; p < 2; ++p)
      for (int q = p + 1; q < 3; ++q) {
        if (std::abs(m[p][q]) < 1e-300) continue;
        const double th = 0.5 * std::atan2(2 * m[p][q], m[q][q] - m[p][p]);
        const double c = std::cos(th), s = std::sin(th);
        for (int k = 0; k < 3; ++k) {  // columns
          const double mkp = m[k][p], mkq = m[k][q];
          m[k][p] = c * mkp - s * mkq;
          m[k][q] = s * mkp + c * mkq;
        }
        for (int k = 0; k < 3; ++k) {  // rows
          const double mpk = m[p][k], mqk = m[q][k];
          m[p][k] = c * mpk - s * mqk;
          m[q][k] = s * mpk + c * mqk;
        }
      }
  }
  for (int k = 0; k < 3; ++k) ev[k] = m[k][k];
  std::sort(ev, ev + 3, [](double a, double b) { return a > b; });
}

}  // namespace

std::vector<ParticleShape> ParticleTracker::from_spheres(const std::vector<Sphere>& s) {
  std::vector<ParticleShape> v(s.size());
  for (size_t m = 0; m < s.size(); ++m) v[m].x = s[m].x, v[m].y = s[m].y, v[m].z = s[m].z;
  return v;
}

ParticleTracker::ParticleTracker(FlowSolver& s, const std::vector<ParticleShape>& start)
    : s_(s),
      shapes_(start),
      centres_("tracker_centres", start.size()),
      moments_("tracker_moments", start.size()) {}

void ParticleTracker::update() {
  const int n = int(shapes_.size());
  if (n == 0 || !s_.solid()) return;
  auto ch = Kokkos::create_mirror_view(centres_);
  for (int m = 0; m < n; ++m) ch(m, 0) = shapes_[m].x, ch(m, 1) = shapes_[m].y, ch(m, 2) = shapes_[m].z;
  Kokkos::deep_copy(centres_, ch);
  Kokkos::deep_copy(moments_, 0.0);
  const Grid g = s_.grid();
  const SolidViews sv(s_.solid()->fields());
  auto c = centres_;
  auto mom = moments_;
  const Real r = s_.config().particles.radius, lx = g.lx, lz = g.lz;
  const Real cut2 = 4 * r * r;
  par_for(
      "tracker_moments", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
        const Real f = fraction(sv.phi(i, j, k));
        if (f <= 0) return;
        const Real x = g.xc(i), y = g.yc(j), z = g.zc(k);
        int best = -1;
        Real bd = cut2, bx = 0, by = 0, bz = 0;
        for (int m = 0; m < n; ++m) {
          Real dx = x - c(m, 0), dy = y - c(m, 1), dz = z - c(m, 2);
          dx -= lx * Kokkos::round(dx / lx);
          dz -= lz * Kokkos::round(dz / lz);
          const Real d2 = dx * dx + dy * dy + dz * dz;
          if (d2 < bd) bd = d2, best = m, bx = dx, by = dy, bz = dz;
        }
        if (best < 0) return;
        const Real mv[n_moments] = {f,
                                    f * bx,
                                    f * by,
                                    f * bz,
                                    f * bx * bx,
                                    f * bx * by,
                                    f * bx * bz,
                                    f * by * by,
                                    f * by * bz,
                                    f * bz * bz,
                                    f * sv.B(0, i, j, k),
                                    f * sv.B(1, i, j, k),
                                    f * sv.B(2, i, j, k),
                                    f * sv.B(3, i, j, k),
                                    f * sv.B(4, i, j, k),
                                    f * sv.B(5, i, j, k)};
        for (int e = 0; e < n_moments; ++e) Kokkos::atomic_add(&mom(best, e), mv[e]);
      });
  auto mh = Kokkos::create_mirror_view(moments_);
  Kokkos::deep_copy(mh, moments_);
  std::vector<double> buf(mh.data(), mh.data() + n_moments * n);
  MPI_Allreduce(MPI_IN_PLACE, buf.data(), n_moments * n, MPI_DOUBLE, MPI_SUM, s_.decomposition().comm);
  const double dv = g.dx * g.dy * g.dz;
  for (int m = 0; m < n; ++m) {
    const double* q = &buf[n_moments * m];
    ParticleShape& p = shapes_[m];
    if (q[0] <= 0) continue;  // lost: keep the old centroid
    const double mx = q[1] / q[0], my = q[2] / q[0], mz = q[3] / q[0];
    p.x = std::fmod(p.x + mx + lx, lx);
    p.y += my;
    p.z = std::fmod(p.z + mz + lz, lz);
    p.volume = q[0] * dv;
    double cov[3][3] = {{q[4] / q[0] - mx * mx, q[5] / q[0] - mx * my, q[6] / q[0] - mx * mz},
                        {0, q[7] / q[0] - my * my, q[8] / q[0] - my * mz},
                        {0, 0, q[9] / q[0] - mz * mz}};
    cov[1][0] = cov[0][1], cov[2][0] = cov[0][2], cov[2][1] = cov[1][2];
    const double cxx = cov[0][0], cxy = cov[0][1], cyy = cov[1][1];
    double ev[3];
    eig3(cov, ev);
    p.a = std::sqrt(5 * std::max(ev[0], 0.0));
    p.b = std::sqrt(5 * std::max(ev[1], 0.0));
    p.c = std::sqrt(5 * std::max(ev[2], 0.0));
    const double tr = 0.5 * (cxx + cyy), dif = std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
    p.a_xy = std::sqrt(5 * std::max(tr + dif, 0.0));
    p.b_xy = std::sqrt(5 * std::max(tr - dif, 0.0));
    // The diffuse interface's tails inflate the second moments alike in every
    // direction: the moments give the shape, the particle's volume its size.
    // Scale the axes so that (4/3) pi a b c is that volume (T is unchanged).
    const double abc = p.a * p.b * p.c;
    p.axes_scale = abc > 0 ? std::cbrt(p.volume / (4.0 / 3.0 * M_PI * abc)) : 1.0;
    p.a *= p.axes_scale, p.b *= p.axes_scale, p.c *= p.axes_scale;
    p.a_xy *= p.axes_scale, p.b_xy *= p.axes_scale;
    p.taylor = (p.a_xy - p.b_xy) / (p.a_xy + p.b_xy);
    p.angle = 0.5 * std::atan2(2 * cxy, cxx - cyy);
    // The same x-y section from the solid's own record of its deformation:
    // a homogeneously deformed sphere is the ellipsoid x^T B^-1 x = r^2, whose
    // second moments are (r^2 / 5) B. Where phi and B were transported
    // consistently the two agree; a gap between them is shape drift that no
    // elastic stress restores.
    const double bxx = q[10] / q[0], bxy = q[11] / q[0], byy = q[13] / q[0];
    const double btr = 0.5 * (bxx + byy), bdif = std::sqrt(0.25 * (bxx - byy) * (bxx - byy) + bxy * bxy);
    const double ba = std::sqrt(std::max(btr + bdif, 0.0)), bb = std::sqrt(std::max(btr - bdif, 0.0));
    p.taylor_b = ba + bb > 0 ? (ba - bb) / (ba + bb) : 0.0;
    p.angle_b = 0.5 * std::atan2(2 * bxy, bxx - byy);
  }
}

}  // namespace softflow
