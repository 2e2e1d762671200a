#include "particle_tracker.hpp"

#include <algorithm>
#include <cmath>

#include "../kernels/mixture_stress.hpp"

namespace softflow {

namespace {

// eigen-decomposition of a symmetric 3x3 matrix (Jacobi rotations):
// eigenvalues descending, vec[k] the unit eigenvector of ev[k]
void eig3(double m[3][3], double ev[3], double vec[3][3]) {
  double v[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};  // columns: the eigenvectors
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
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
        for (int k = 0; k < 3; ++k) {  // rows
          const double mpk = m[p][k], mqk = m[q][k];
          m[p][k] = c * mpk - s * mqk;
          m[q][k] = s * mpk + c * mqk;
        }
      }
  }
  int order[3] = {0, 1, 2};
  std::sort(order, order + 3, [&](int a, int b) { return m[a][a] > m[b][b]; });
  for (int k = 0; k < 3; ++k) {
    ev[k] = m[order[k]][order[k]];
    for (int e = 0; e < 3; ++e) vec[k][e] = v[e][order[k]];
  }
}

// The ellipsoid of the cells whose moments (sum f, f x (3), f x x (6), x
// relative to the tracked centroid) q holds: their centroid offset, the
// covariance, its eigenvalues (descending) and eigenvectors.
struct Spread {
  double mean[3], cov[3][3], ev[3], vec[3][3];
};
Spread spread_of(const double* q) {
  Spread s{};
  for (int d = 0; d < 3; ++d) s.mean[d] = q[1 + d] / q[0];
  const int a_of[6] = {0, 0, 0, 1, 1, 2}, b_of[6] = {0, 1, 2, 1, 2, 2};
  for (int e = 0; e < 6; ++e) {
    const int a = a_of[e], b = b_of[e];
    s.cov[a][b] = s.cov[b][a] = q[4 + e] / q[0] - s.mean[a] * s.mean[b];
  }
  double work[3][3];
  std::copy(&s.cov[0][0], &s.cov[0][0] + 9, &work[0][0]);
  eig3(work, s.ev, s.vec);
  return s;
}

// the semi-axes of a uniform ellipsoid with covariance eigenvalues ev and
// volume v (the diffuse interface's tails inflate the moments alike in every
// direction: the moments give the shape, the volume its size); scale = the
// factor applied to sqrt(5 ev)
void axes_of(const double ev[3], double v, double ax[3], double& scale) {
  for (int k = 0; k < 3; ++k) ax[k] = std::sqrt(5 * std::max(ev[k], 0.0));
  const double abc = ax[0] * ax[1] * ax[2];
  scale = abc > 0 ? std::cbrt(v / (4.0 / 3.0 * M_PI * abc)) : 1.0;
  for (int k = 0; k < 3; ++k) ax[k] *= scale;
}

// the reach of a particle with semi-axes ax[k] along vec[k] (see the header):
// M = sum_k vec_k vec_k^T / (4/3 (ax_k + r/2))^2
void reach_metric(const double ax[3], const double vec[3][3], double r, double out[6]) {
  const int a_of[6] = {0, 0, 0, 1, 1, 2}, b_of[6] = {0, 1, 2, 1, 2, 2};
  for (int e = 0; e < 6; ++e) out[e] = 0;
  for (int k = 0; k < 3; ++k) {
    const double l = 4.0 / 3.0 * (ax[k] + r / 2);
    for (int e = 0; e < 6; ++e) out[e] += vec[k][a_of[e]] * vec[k][b_of[e]] / (l * l);
  }
}

// a cell's moments for particle m, at offset d from its centroid, into row m
// of the moments: sum f, f d, f d d, f B, and the same first ten over the
// core (f > 1/2), whose ellipsoid sets the reach
template <class Moments>
struct AddCell {
  Moments mom;
  SolidViews sv;
  KOKKOS_INLINE_FUNCTION void operator()(int m, Real f, const Real d[3], int i, int j, int k) const {
    const Real mv[16] = {f,
                         f * d[0],
                         f * d[1],
                         f * d[2],
                         f * d[0] * d[0],
                         f * d[0] * d[1],
                         f * d[0] * d[2],
                         f * d[1] * d[1],
                         f * d[1] * d[2],
                         f * d[2] * d[2],
                         f * sv.B(0, i, j, k),
                         f * sv.B(1, i, j, k),
                         f * sv.B(2, i, j, k),
                         f * sv.B(3, i, j, k),
                         f * sv.B(4, i, j, k),
                         f * sv.B(5, i, j, k)};
    for (int e = 0; e < 16; ++e) Kokkos::atomic_add(&mom(m, e), mv[e]);
    if (f <= Real(0.5)) return;
    for (int e = 0; e < 10; ++e) Kokkos::atomic_add(&mom(m, 16 + e), mv[e]);
  }
};

// the offset d of cell (i, j, k) from particle m's centroid (periodic in x
// and z), and d^T M d with M its reach metric (within reach below 1)
template <class Centres, class Metric>
struct ReachOf {
  Centres c;
  Metric M;
  Grid g;
  KOKKOS_INLINE_FUNCTION Real operator()(int m, int i, int j, int k, Real d[3]) const {
    d[0] = g.xc(i) - c(m, 0), d[1] = g.yc(j) - c(m, 1), d[2] = g.zc(k) - c(m, 2);
    d[0] -= g.lx * Kokkos::round(d[0] / g.lx);
    d[2] -= g.lz * Kokkos::round(d[2] / g.lz);
    return M(m, 0) * d[0] * d[0] + M(m, 3) * d[1] * d[1] + M(m, 5) * d[2] * d[2] +
           2 * (M(m, 1) * d[0] * d[1] + M(m, 2) * d[0] * d[2] + M(m, 4) * d[1] * d[2]);
  }
};

}  // namespace

std::vector<ParticleShape> ParticleTracker::from_spheres(const std::vector<Sphere>& s,
                                                         const ParticleConfig& p) {
  std::vector<ParticleShape> v(s.size());
  for (size_t m = 0; m < s.size(); ++m) v[m].x = s[m].x, v[m].y = s[m].y, v[m].z = s[m].z;
  if (!p.deformed_start()) return v;  // the seeded sphere's reach (update())
  // the seeded ellipsoid x^T B^-1 x = r^2: semi-axes r sqrt(eigenvalues of B)
  const Real* b = p.initial_b;
  double m[3][3] = {{b[0], b[1], b[2]}, {b[1], b[3], b[4]}, {b[2], b[4], b[5]}}, ev[3], vec[3][3], ax[3];
  eig3(m, ev, vec);
  for (int k = 0; k < 3; ++k) ax[k] = p.radius * std::sqrt(ev[k]);
  double reach[6];
  reach_metric(ax, vec, p.radius, reach);
  for (auto& shape : v) std::copy(reach, reach + 6, shape.reach);
  return v;
}

ParticleTracker::ParticleTracker(FlowSolver& s, const std::vector<ParticleShape>& start)
    : s_(s),
      shapes_(start),
      centres_("tracker_centres", start.size()),
      reach_("tracker_reach", start.size()),
      moments_("tracker_moments", start.size()),
      centres_host_(Kokkos::create_mirror_view(centres_)),
      reach_host_(Kokkos::create_mirror_view(reach_)),
      moments_host_(Kokkos::create_mirror_view(moments_)) {}

void ParticleTracker::update() {
  const int n = int(shapes_.size());
  if (n == 0 || !s_.solid()) return;
  const Real r = s_.config().particles.radius;
  const auto ch = centres_host_;
  const auto rh = reach_host_;
  for (int m = 0; m < n; ++m) {
    const ParticleShape& p = shapes_[m];
    ch(m, 0) = p.x, ch(m, 1) = p.y, ch(m, 2) = p.z;
    const bool measured = p.reach[0] > 0;  // else the seeded sphere: 2 r
    for (int e = 0; e < 6; ++e) rh(m, e) = measured ? p.reach[e] : (e == 0 || e == 3 || e == 5) / (4 * r * r);
  }
  Kokkos::deep_copy(centres_, ch);
  Kokkos::deep_copy(reach_, rh);
  Kokkos::deep_copy(moments_, 0.0);
  const Grid g = s_.grid();
  const SolidViews sv(s_.solid()->fields());
  auto c = centres_;
  auto M = reach_;
  auto mom = moments_;
  const Real lx = g.lx, lz = g.lz;
  const AddCell<decltype(moments_)> add{mom, sv};
  const ReachOf<decltype(centres_), decltype(reach_)> reach{c, M, g};
  const ColourFields& colours = s_.solid()->colours();
  if (colours.size() == n) {
    // one colour per particle: each particle is its own colour's cells within
    // its reach, whoever else is near. Splitting the summed phi between
    // touching particles by the nearest reach gives each a piece of the
    // other; at Ca = 2, Phi = 0.11, 4 ppr that read T 0.50-0.64 where the
    // colours held 0.72-0.76 and B 0.71-0.73 (results/README.md, round 28)
    for (int m = 0; m < n; ++m) {
      const Field3 q = colours.colour(m);
      const ColourBoxes& on = colours.update_boxes(m);  // it is 0 outside them
      for (int b = 0; b < on.count; ++b)
        par_for(
            "tracker_colour_moments", on.box[b], KOKKOS_LAMBDA(int i, int j, int k) {
              const Real f = fraction(q(i, j, k));
              if (f <= 0) return;
              Real d[3];
              if (reach(m, i, j, k, d) < 1) add(m, f, d, i, j, k);
            });
    }
  } else {
    par_for(
        "tracker_moments", g.interior(), KOKKOS_LAMBDA(int i, int j, int k) {
          const Real f = fraction(sv.phi(i, j, k));
          if (f <= 0) return;
          int best = -1;
          Real bd = 1, bdist[3] = {0, 0, 0};  // within reach: d^T M d < 1
          for (int m = 0; m < n; ++m) {
            Real d[3];
            const Real d2 = reach(m, i, j, k, d);
            if (d2 < bd) bd = d2, best = m, bdist[0] = d[0], bdist[1] = d[1], bdist[2] = d[2];
          }
          if (best >= 0) add(best, f, bdist, i, j, k);
        });
  }
  const auto mh = moments_host_;
  Kokkos::deep_copy(mh, moments_);
  MPI_Allreduce(MPI_IN_PLACE, mh.data(), n_moments * n, MPI_DOUBLE, MPI_SUM, s_.decomposition().comm);
  const double dv = g.dx * g.dy * g.dz;
  for (int m = 0; m < n; ++m) {
    const double* q = mh.data() + n_moments * m;
    ParticleShape& p = shapes_[m];
    if (q[0] <= 0) continue;  // lost: keep the old centroid
    const Spread all = spread_of(q);
    p.x = std::fmod(p.x + all.mean[0] + lx, lx);
    p.y += all.mean[1];
    p.z = std::fmod(p.z + all.mean[2] + lz, lz);
    p.volume = q[0] * dv;
    double ax[3];
    axes_of(all.ev, p.volume, ax, p.axes_scale);
    p.a = ax[0], p.b = ax[1], p.c = ax[2];
    const double cxx = all.cov[0][0], cxy = all.cov[0][1], cyy = all.cov[1][1];
    const double tr = 0.5 * (cxx + cyy), dif = std::sqrt(0.25 * (cxx - cyy) * (cxx - cyy) + cxy * cxy);
    p.a_xy = p.axes_scale * std::sqrt(5 * std::max(tr + dif, 0.0));
    p.b_xy = p.axes_scale * std::sqrt(5 * std::max(tr - dif, 0.0));
    // the reach from the core (phi > 0.5) alone: wisps of solid shed into the
    // fluid would otherwise widen it, and it would take in more of them at
    // the next update. A particle with no core cell keeps its reach.
    const double* core = q + 16;
    if (core[0] > 0) {
      const Spread cs = spread_of(core);
      double cax[3], cscale;
      axes_of(cs.ev, core[0] * dv, cax, cscale);
      reach_metric(cax, cs.vec, r, p.reach);
    }
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
