// Random placement by relaxation: N centres are drawn uniformly in the region
// allowed by the walls, then overlapping pairs (closer than the target
// distance, with the minimum image in x and z) are pushed apart symmetrically,
// sweep after sweep, while the target distance grows from 70% to 2r + gap over
// the first sweeps (a gentle Lubachevsky-Stillinger-like growth), until none
// overlap. Random sequential addition jams near Phi = 0.38 and
// much earlier between walls; relaxation packs the reference Phi = 0.33 in a
// few hundred sweeps.
//
// "stratified" (the default) draws the same numbers but turns each wall-normal
// draw into a point of its own y stratum (n equal strata in random order), so
// the spheres start spread evenly across the gap. Independent draws leave a
// small box lopsided: the dense Phi = 0.11 case (10 spheres, seed 1) started
// with its solid's centre 0.86 r below mid-gap and 11% of it within r of a
// wall, and its mu relaxed with that for 50+ strain units (round 21).
//
// The gap is at least a cell diagonal (particles.min_gap_cells = 1) as well as
// min_gap: two spheres closer than that share cells, and their phi bands
// touch above 1/2 from the start. At 4 points per radius the study's 0.1 r is
// 0.23 of a diagonal: the 67 spheres of the reference box started as 35
// bodies above phi = 1/2, and in the dense 8r x 6r x 8r box mu/mu_f fell by
// 1.3-2.3% between strain [10, 30) and [30, 50) in 3 seeds of 3. With the
// gap at 0.45 r (just over a diagonal) the same 3 seeds pass with no trend
// (with a diagonal, 2 of 3: collisions still fuse some particles later;
// results/README.md, round 22). At 16 points per radius a diagonal is
// 0.108 r, next to the study's 0.1 r.
#include "particle_seeding.hpp"

#include <algorithm>

#include <cmath>
#include <random>
#include <sstream>

namespace softflow {

int sphere_count(const Config& c) {
  const ParticleConfig& p = c.particles;
  if (p.count > 0) return p.count;
  const double v = c.grid.lx * c.grid.ly * c.grid.lz;
  const double vs = 4.0 / 3.0 * M_PI * p.radius * p.radius * p.radius;
  return std::max(1, int(std::lround(p.volume_fraction * v / vs)));
}

int colour_count(const Config& c) {
  const ParticleConfig& p = c.particles;
  if (p.shape != "spheres") return 0;
  const int n = sphere_count(c);
  if (p.colour_fields == ParticleConfig::auto_colours) return n >= 2 ? n : 0;
  return std::min(p.colour_fields, n);  // more colours than spheres would only add empty fields
}

double largest_stretch(const Real* b) {
  // the largest eigenvalue of the symmetric B, in closed form (Smith 1961)
  const double q = (b[0] + b[3] + b[5]) / 3;
  const double p1 = b[1] * b[1] + b[2] * b[2] + b[4] * b[4];
  const double p2 = (b[0] - q) * (b[0] - q) + (b[3] - q) * (b[3] - q) + (b[5] - q) * (b[5] - q) + 2 * p1;
  if (p2 <= 1e-30) return q;
  const double p = std::sqrt(p2 / 6);
  const double c[6] = {(b[0] - q) / p, b[1] / p, b[2] / p, (b[3] - q) / p, b[4] / p, (b[5] - q) / p};
  const double half_det = 0.5 * (c[0] * (c[3] * c[5] - c[4] * c[4]) - c[1] * (c[1] * c[5] - c[4] * c[2]) +
                                 c[2] * (c[1] * c[4] - c[3] * c[2]));
  const double phase = std::acos(std::clamp(half_det, -1.0, 1.0)) / 3;
  return q + 2 * p * std::cos(phase);
}

namespace {
// a deformed start (particles.initial_b): the ellipsoid x^T B^-1 x < r^2
// lies within r sqrt(lambda_max(B)) of its centre and reaches r sqrt(B_yy)
// across y; kept apart as spheres of that radius
double seeding_reach(const ParticleConfig& p) { return p.radius * std::sqrt(largest_stretch(p.initial_b)); }

// an upper bound no packing of hard spheres between walls can beat, for gap g
bool packable(const Config& c, double g) {
  const ParticleConfig& p = c.particles;
  const double dmin = 2 * seeding_reach(p) + g;
  const double ylim = c.grid.ly / 2 - p.radius * std::sqrt(p.initial_b[3]) - g;
  const double occupied = sphere_count(c) * (4.0 / 3.0) * M_PI * std::pow(dmin / 2, 3);
  return ylim >= 0 && dmin <= c.grid.lx && dmin <= c.grid.lz &&
         occupied <= 0.55 * c.grid.lx * (2 * ylim + dmin) * c.grid.lz;
}

// the resolved gap, lowered only as far as the packing bound needs
double bounded_gap(const Config& c) {
  const ParticleConfig& p = c.particles;
  const GridConfig& gr = c.grid;
  const double dx = gr.lx / gr.nx, dy = gr.ly / gr.ny, dz = gr.lz / gr.nz;
  const double resolved = std::max(p.min_gap, p.min_gap_cells * std::sqrt(dx * dx + dy * dy + dz * dz));
  if (packable(c, resolved) || !packable(c, p.min_gap)) return resolved;
  // a dense box at a coarse grid (Phi = 0.33 at 4 points per radius): the
  // largest gap between min_gap and the resolved one that the bound allows
  double lo = p.min_gap, hi = resolved;
  for (int it = 0; it < 60; ++it) (packable(c, 0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  return lo;
}

// The relaxation with gap `gap` into s; false if it jams, which throws only
// when `last` (no smaller gap is left to try)
bool relax(const Config& c, double gap, bool last, std::vector<Sphere>& s) {
  const ParticleConfig& p = c.particles;
  const double lx = c.grid.lx, lz = c.grid.lz, h = c.grid.ly / 2;
  const double r = p.radius, reach = seeding_reach(p);
  const double dmin = 2 * reach + gap;
  const double ylim = h - r * std::sqrt(p.initial_b[3]) - gap;
  const int n = sphere_count(c);
  auto fail = [&](const std::string& why) {
    std::ostringstream m;
    m << "cannot place " << n << " spheres of radius " << r
      << (reach > r ? " (deformed: reach " + std::to_string(reach) + ")" : "") << " with gap " << gap
      << " in the " << lx << " x " << c.grid.ly << " x " << lz << " box (volume fraction "
      << n * 4.0 / 3.0 * M_PI * r * r * r / (lx * c.grid.ly * lz) << "): " << why;
    throw InputError(m.str());
  };
  if (dmin > lx || dmin > lz) fail("the box is narrower than two radii plus the gap");
  if (!packable(c, gap)) fail("too dense for random placement (limit ~0.55)");

  std::mt19937_64 gen(p.seed);
  std::uniform_real_distribution<double> ux(0, lx), uy(-ylim, ylim), uz(0, lz);
  s.assign(n, Sphere{});
  if (p.placement == "stratified") {
    // the same draws, but sphere i's y is (stratum[i] + u) / n of the range
    // where "random" takes u of it (one sphere: the same y to the last bit)
    std::uniform_real_distribution<double> u01(0, 1);
    for (auto& q : s) q = {ux(gen), u01(gen), uz(gen)};
    std::vector<int> stratum(n);
    for (int i = 0; i < n; ++i) stratum[i] = i;
    std::shuffle(stratum.begin(), stratum.end(), gen);
    for (int i = 0; i < n; ++i) s[i].y = ((stratum[i] + s[i].y) / n) * (2 * ylim) - ylim;
  } else {
    for (auto& q : s) q = {ux(gen), uy(gen), uz(gen)};
  }
  auto wrap = [](double x, double l) { return x - l * std::floor(x / l); };
  const int grow = 2000;
  for (int sweep = 0; sweep < 20000; ++sweep) {
    const double target = dmin * (sweep < grow ? 0.7 + 0.3 * sweep / grow : 1.0);
    int overlaps = 0;
    for (int a = 0; a < n; ++a)
      for (int b = a + 1; b < n; ++b) {
        double dx = s[b].x - s[a].x, dy = s[b].y - s[a].y, dz = s[b].z - s[a].z;
        dx -= lx * std::round(dx / lx);
        dz -= lz * std::round(dz / lz);
        const double d = std::sqrt(dx * dx + dy * dy + dz * dz);
        if (d >= target) continue;
        ++overlaps;
        double ex = dx, ey = dy, ez = dz, dd = d;
        if (dd < 1e-12) {  // coincident: push along a random direction
          ex = ux(gen) - lx / 2, ey = uy(gen), ez = uz(gen) - lz / 2;
          dd = std::sqrt(ex * ex + ey * ey + ez * ez);
        }
        // a little beyond the target, so that round-off does not leave pairs just short of it
        const double push = 0.5 * (target * (1 + 1e-6) - d) / dd;
        s[a].x -= ex * push, s[a].y -= ey * push, s[a].z -= ez * push;
        s[b].x += ex * push, s[b].y += ey * push, s[b].z += ez * push;
      }
    for (auto& q : s) {
      q.x = wrap(q.x, lx);
      q.z = wrap(q.z, lz);
      q.y = std::clamp(q.y, -ylim, ylim);
    }
    if (overlaps == 0 && sweep >= grow) return true;
  }
  if (last) fail("no overlap-free arrangement found in 20000 relaxation sweeps");
  return false;
}

struct Placement {
  std::vector<Sphere> spheres;
  double gap;
};

// The relaxation jams before the packing bound in a small dense box (30
// spheres, Phi = 0.33, 8r x 6r x 8r at 4 points per radius): a gap above
// min_gap is then lowered towards it in steps, never below it
Placement place(const Config& c) {
  const ParticleConfig& p = c.particles;
  const double first = bounded_gap(c), floor = p.min_gap;
  if (p.placement == "centre") return {{{c.grid.lx / 2, 0, c.grid.lz / 2}}, first};
  Placement out{{}, first};
  for (const double f : {1.0, 0.5, 0.25, 0.0}) {
    out.gap = floor + f * (first - floor);
    const bool last = f == 0.0 || first <= floor;
    if (relax(c, out.gap, last, out.spheres)) return out;
  }
  return out;  // not reached: the last try throws
}
}  // namespace

double seeding_gap(const Config& c) { return place(c).gap; }

std::vector<Sphere> seed_spheres(const Config& c) { return place(c).spheres; }

}  // namespace softflow
